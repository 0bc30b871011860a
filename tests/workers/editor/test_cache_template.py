"""A node's browsers start from one warm cache: the template is written once and whole, only by a browser
that closed cleanly after two editor openings, and a browser started from it runs the editor bundle from
V8's code cache at its first opening."""

from __future__ import annotations

import asyncio
import json
from pathlib import Path

import psutil
import pytest

from workers.editor import BrowserSession, EditorAssets
from workers.editor._cache_template import CACHE_DIRS, PROFILE, TEMPLATE_ENV, CacheTemplate, default_templates_dir
from workers.node import BUNDLE_FILE, default_chromium


def _profile(root: Path, content: str) -> Path:
    """A closed browser's profile as far as the template goes: its two cache folders, one file each."""
    for name in CACHE_DIRS:
        (root / PROFILE / name).mkdir(parents=True)
        (root / PROFILE / name / "entry").write_text(content)
    return root


def test_a_template_is_kept_once_whole_and_copied_into_new_profiles(tmp_path: Path) -> None:
    template = CacheTemplate(tmp_path / "templates", default_chromium(), "bundle")
    fresh = tmp_path / "fresh"
    fresh.mkdir()
    assert not template.seed(fresh) and list(fresh.iterdir()) == []  # none yet: the browser starts empty

    assert not template.offer(tmp_path / "no-caches")  # a profile without both caches is not kept
    assert template.offer(_profile(tmp_path / "first", "first"))
    assert not template.offer(_profile(tmp_path / "second", "second"))  # written once: the first stays
    assert template.seed(fresh)
    for name in CACHE_DIRS:
        assert (fresh / PROFILE / name / "entry").read_text() == "first"
    assert [path.name for path in template.path.parent.iterdir()] == [template.path.name]  # nothing half made


def test_each_chromium_build_and_editor_bundle_has_its_own_template(tmp_path: Path) -> None:
    other = tmp_path / "chromium"
    other.write_bytes(default_chromium().read_bytes()[:1000])
    kept = CacheTemplate(tmp_path, default_chromium(), "bundle")
    assert kept.offer(_profile(tmp_path / "used", "used"))
    assert not CacheTemplate(tmp_path, other, "bundle").exists
    assert not CacheTemplate(tmp_path, default_chromium(), "another bundle").exists  # offered afresh
    assert CacheTemplate(tmp_path, default_chromium(), "bundle").exists


def test_templates_live_where_the_node_says_or_nowhere(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.setenv(TEMPLATE_ENV, str(tmp_path))
    assert default_templates_dir() == tmp_path
    monkeypatch.setenv(TEMPLATE_ENV, "off")
    assert CacheTemplate.for_node(default_chromium(), "bundle") is None
    monkeypatch.delenv(TEMPLATE_ENV)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert default_templates_dir() == tmp_path / "scratchworld_dist" / "browser-cache"


async def _bundle_compile(session: BrowserSession) -> dict[str, object]:
    """How V8 compiled the editor bundle at one editor opening (its trace's ``v8.compile`` event)."""
    browser = session._browser
    assert browser is not None
    await browser.start_tracing(categories=["v8"])
    try:
        editor = await session.open_editor()
    finally:
        trace = json.loads(await browser.stop_tracing())
    await editor.close()
    events = trace["traceEvents"] if isinstance(trace, dict) else trace
    compiles = [
        event["args"]["data"]
        for event in events
        if event.get("name") == "v8.compile" and BUNDLE_FILE in event.get("args", {}).get("data", {}).get("url", "")
    ]
    assert len(compiles) == 1, compiles
    return compiles[0]


@pytest.mark.browser
@pytest.mark.slow  # three browsers, four of their openings compiling the bundle: about 30 s on 2 cores
async def test_a_browser_started_from_the_template_runs_the_bundle_from_the_code_cache_at_once(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    monkeypatch.setenv(TEMPLATE_ENV, str(tmp_path))
    template = CacheTemplate.for_node(default_chromium(), EditorAssets().bundle_version)
    assert template is not None

    async with BrowserSession() as dying:  # two openings, then the browser dies: its caches may be half written
        assert "consumedCacheSize" not in await _bundle_compile(dying)  # a fresh browser compiles the bundle
        await (await dying.open_editor()).close()
        psutil.Process(await dying.browser_pid()).kill()
        for _ in range(400):  # bounded: the disconnect arrives a moment after the kill
            if not dying.connected:
                break
            await asyncio.sleep(0.05)
        assert not dying.connected
    assert not template.exists

    async with BrowserSession() as first:
        for _ in range(2):
            await (await first.open_editor()).close()
    assert template.exists

    async with BrowserSession() as seeded:
        compiled = await _bundle_compile(seeded)
    assert compiled.get("cacheRejected") is False and int(compiled.get("consumedCacheSize", 0)) > 1_000_000, compiled
