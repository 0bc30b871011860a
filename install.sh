#!/usr/bin/env bash
# Installs everything scratchworld_dist needs on a Debian machine, idempotently:
#   - Debian's chromium (Playwright's own browser download does not work here) and Node.js/npm,
#   - a Python 3.11 virtualenv in .venv with the package and its dev tools, installed by uv (pip took
#     37 s here). Bytecode is compiled at install, as pip does: with PYTHONDONTWRITEBYTECODE set (it is
#     here) nothing else would write it, and every Ray worker and CLI process would compile its imports.
#   - the Scratch editor bundle from npm (scratch-gui/node_modules), the one package pinned by
#     package-lock.json and checked against the lock's integrity; its ~740 dependencies are built
#     into the bundle's dist already, so `npm ci` (1.1 GB, 24 s) would fetch them for nothing,
#   - the bare evaluation page's packages (scratch-gui/bare, its own lock) and its scratch-audio build,
#   - the editor bundle re-encoded to ASCII by the bare page's esbuild (a waiting editor's memory), and its
#     translations but English's built on first use (workers/node/_lazy_locales.py).
# Safe to re-run: steps that are already done are skipped.
set -euo pipefail
cd "$(dirname "$0")"

say() { printf '[install] %s\n' "$*"; }
as_root() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }

apt_packages=()
[ -x /usr/bin/chromium ] || apt_packages+=(chromium)
command -v npm >/dev/null 2>&1 || apt_packages+=(nodejs npm)
command -v python3.11 >/dev/null 2>&1 || python3 -c 'import sys; assert sys.version_info[:2] == (3, 11)' 2>/dev/null \
  || apt_packages+=(python3.11 python3.11-venv)
if [ ${#apt_packages[@]} -gt 0 ]; then
  say "apt-get install ${apt_packages[*]}"
  as_root apt-get update -qq
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${apt_packages[@]}" >/dev/null
fi

python_bin=$(command -v python3.11 || command -v python3)
if [ ! -x .venv/bin/python ]; then
  say "creating .venv with $python_bin"
  "$python_bin" -m venv .venv
fi
# Reinstall only when the project's metadata changed since the last install.
stamp=.venv/.installed-$(sha256sum pyproject.toml | cut -c1-16)
if [ ! -f "$stamp" ]; then
  say "uv pip install -e .[dev]"
  [ -x .venv/bin/uv ] || .venv/bin/python -m pip install -q uv
  .venv/bin/uv pip install -q --compile-bytecode --python .venv/bin/python -e ".[dev]"
  rm -f .venv/.installed-* && touch "$stamp"
fi

bundle=scratch-gui/node_modules/@scratch/scratch-gui-standalone/dist/scratch-gui-standalone.js
lock_stamp=scratch-gui/node_modules/.installed-$(sha256sum scratch-gui/package-lock.json | cut -c1-16)
if [ ! -f "$bundle" ] || [ ! -f "$lock_stamp" ]; then
  package=@scratch/scratch-gui-standalone
  locked() { node -e 'const p = require(process.argv[1]).packages["node_modules/" + process.argv[2]];
    process.stdout.write(p[process.argv[3]])' "$PWD/scratch-gui/package-lock.json" "$package" "$1"; }
  version=$(locked version) integrity=$(locked integrity)
  say "npm pack $package@$version (the Scratch editor bundle)"
  download=$(mktemp -d)
  trap 'rm -rf "$download"' EXIT
  npm pack "$package@$version" --pack-destination "$download" --json --loglevel=error > "$download/pack.json"
  packed=$(node -e 'process.stdout.write(require(process.argv[1])[0].integrity)' "$download/pack.json")
  if [ "$packed" != "$integrity" ]; then
    echo "[install] $package@$version does not match scratch-gui/package-lock.json's integrity" >&2
    exit 1
  fi
  target=scratch-gui/node_modules/$package
  rm -rf scratch-gui/node_modules && mkdir -p "$target"
  tar -xzf "$download"/*.tgz -C "$target" --strip-components=1
  touch "$lock_stamp"
fi
# The bare evaluation page (scratch-gui/bare.html): the VM, renderer, storage and SVG renderer packages,
# whose browser builds it loads as they are, and scratch-audio, which esbuild bundles into one browser
# script. Their own lock; ~250 packages, ~25 s.
bare=scratch-gui/bare
bare_stamp=$bare/node_modules/.installed-$(sha256sum $bare/package-lock.json | cut -c1-16)
if [ ! -f "$bare_stamp" ] || [ ! -f "$bare/build/scratch-audio.js" ]; then
  say "npm ci in $bare (the bare evaluation page's packages)"
  (cd "$bare" && npm ci --ignore-scripts --no-audit --no-fund --loglevel=error >/dev/null \
    && node_modules/.bin/esbuild node_modules/scratch-audio/dist.js --bundle --format=iife --global-name=AudioEngine \
      --platform=browser --log-level=warning --outfile=build/scratch-audio.js)
  touch "$bare_stamp"
fi
# The editor bundle re-encoded to ASCII, in place (esbuild, from the bare page's packages): its 411,097
# characters above U+00FF (mostly scratch-l10n's translations) make every page keep the whole 17 MB source
# two bytes per character. Escaped, a waiting editor holds 12-14 MB less (181-183 -> 169-171 MB PSS by
# `scratchworld capacity`); the code is the same.
ascii_stamp=scratch-gui/node_modules/.ascii-$(sha256sum $bare/package-lock.json | cut -c1-16)
if [ ! -f "$ascii_stamp" ]; then
  say "esbuild --charset=ascii on the editor bundle"
  $bare/node_modules/.bin/esbuild "$bundle" --charset=ascii --minify-whitespace --log-level=warning \
    --outfile="$bundle.ascii"
  mv "$bundle.ascii" "$bundle"
  touch "$ascii_stamp"
fi
# Every language of the editor bundle but English built on first use, in place (see the module): an
# opening neither reads 80 languages' messages from V8's code cache nor builds them.
lazy_stamp=scratch-gui/node_modules/.lazy-locales-$(sha256sum workers/node/_lazy_locales.py | cut -c1-16)
if [ ! -f "$lazy_stamp" ]; then
  say "the editor bundle's languages but English built on first use"
  .venv/bin/python -m workers.node._lazy_locales "$bundle"
  rm -f scratch-gui/node_modules/.lazy-locales-* && touch "$lazy_stamp"
fi
say "done: chromium $(/usr/bin/chromium --version 2>/dev/null | awk '{print $2}'), $(.venv/bin/python --version)"
