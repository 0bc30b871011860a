"""The static server: our files over the npm bundle, loopback only, nothing outside its roots."""

from __future__ import annotations

import http.client
import urllib.error
import urllib.request
from pathlib import Path

import pytest

from scratchworld_dist import EditorBundleMissingError
from tests.conftest import copy_page_files, link_installed_packages
from workers.editor import EditorAssets, EditorServer
from workers.editor._origins import SHARED_ORIGIN, EditorOrigins
from workers.editor._server import REFUSALS_KEPT
from workers.node import BARE_BUILT_FILES, BUNDLE_FILE, EDITOR_PAGE


def _get(url: str) -> tuple[int, bytes]:
    try:
        with urllib.request.urlopen(url, timeout=10) as response:
            return response.status, response.read()
    except urllib.error.HTTPError as exc:
        return exc.code, b""


def test_serves_our_page_bridge_and_the_bundle() -> None:
    with EditorServer() as server:
        base = server.url.rsplit("/", 1)[0]
        assert server.url.startswith("http://127.0.0.1:")
        status, page = _get(server.url)
        assert status == 200 and b"scratchworld.attachVm" in page
        status, bridge = _get(f"{base}/bridge.js")
        assert status == 200
        assert b"Object.defineProperty(window, 'scratchworld'" in bridge
        status, bundle = _get(f"{base}/scratch-gui-standalone.js")
        assert status == 200 and len(bundle) > 10_000_000
        assert _get(f"{base}/static/blocks-media/default/green-flag.svg")[0] == 200


def test_the_bundle_has_no_character_the_browser_would_keep_in_two_bytes() -> None:
    """install.sh re-encodes the bundle to ASCII: a source with any character above U+00FF is held two bytes per
    character, and every editor would hold its 17 MB so (12-14 MB PSS more per waiting editor)."""
    with EditorServer() as server:
        status, bundle = _get(f"{server.url.rsplit('/', 1)[0]}/{BUNDLE_FILE}")
    text = bundle.decode("utf-8")
    wide = sum(character > "\xff" for character in text)
    assert status == 200 and len(text) > 10_000_000
    assert wide == 0, f"{wide} characters above U+00FF: run ./install.sh"


@pytest.mark.parametrize("path", ["/../../pyproject.toml", "/%2e%2e/%2e%2e/pyproject.toml", "/chunks/", "/nothing.js"])
def test_refuses_paths_outside_the_roots(path: str) -> None:
    with EditorServer() as server:
        base = server.url.rsplit("/", 1)[0]
        assert _get(base + path)[0] == 404


def test_missing_bundle_is_a_clear_error(tmp_path: Path) -> None:
    copy_page_files(tmp_path)
    with pytest.raises(EditorBundleMissingError, match=r"is missing; run \./install\.sh"):
        EditorAssets(tmp_path)


def test_a_symlinked_node_modules_is_served(tmp_path: Path) -> None:
    """node_modules may be a link (a shared install, a git worktree, pnpm): its files are inside the root."""
    real = EditorAssets()
    copy_page_files(tmp_path)
    (tmp_path / "node_modules").symlink_to((real.gui_dir / "node_modules").resolve(), target_is_directory=True)
    with EditorServer(EditorAssets(tmp_path)) as server:
        base = server.url.rsplit("/", 1)[0]
        status, bundle = _get(f"{base}/scratch-gui-standalone.js")
        assert status == 200 and len(bundle) > 10_000_000


def test_the_bundle_has_a_version_whether_or_not_a_page_loads_it(tmp_path: Path) -> None:
    """The node's cache template is kept per bundle version, also for pages that never load the bundle."""
    real = EditorAssets()
    assert real.bundle_version == real.script_versions[BUNDLE_FILE]
    copy_page_files(tmp_path)
    link_installed_packages(tmp_path)
    (tmp_path / EDITOR_PAGE).write_text('<!DOCTYPE html><script src="bridge.js"></script>')
    assets = EditorAssets(tmp_path)
    assert BUNDLE_FILE not in assets.script_versions and assets.bundle_version == real.bundle_version


def test_an_edited_page_module_gets_a_new_version_and_no_other_does(tmp_path: Path) -> None:
    """Modules are cached by URL (a browser keeps them for a day): an edit must change the URL."""
    copy_page_files(tmp_path)
    link_installed_packages(tmp_path)
    before = EditorAssets(tmp_path).script_versions
    with (tmp_path / "clock.js").open("a") as clock:
        clock.write("\n// edited\n")
    after = EditorAssets(tmp_path).script_versions
    assert set(before) == set(after) and EDITOR_PAGE not in before and "bridge.js" in before
    assert [name for name in before if before[name] != after[name]] == ["clock.js"]


def _proxied(server: EditorServer, method: str, url: str) -> int:
    """A request sent to the server as to a proxy, as Chromium sends all of a page's requests."""
    host, port = server.proxy.removeprefix("http://").split(":")
    connection = http.client.HTTPConnection(host, int(port), timeout=10)
    try:
        connection.request(method, url)
        return connection.getresponse().status
    finally:
        connection.close()


def test_a_pages_refused_attempt_stays_in_view_through_repeated_background_calls() -> None:
    """Chromium's own update checks differ only in their query (a fresh key each); they count as one."""
    with EditorServer() as server:
        assert _proxied(server, "GET", "http://device-manager.example/scratch/ble") == 403
        for key in range(REFUSALS_KEPT + 50):
            assert _proxied(server, "POST", f"http://update.example/service/update2/json?cup2key={key}") == 403
        assert server.refusals.count == REFUSALS_KEPT + 51
        assert server.refusals.latest == [
            "GET http://device-manager.example/scratch/ble",
            "POST http://update.example/service/update2/json",
        ]


def _asked(server: EditorServer, url: str, headers: dict[str, str]) -> tuple[int, dict[str, str], bytes]:
    """A proxied GET with the headers Chromium would set (``Sec-Fetch-*``: pages cannot set them)."""
    host, port = server.proxy.removeprefix("http://").split(":")
    connection = http.client.HTTPConnection(host, int(port), timeout=10)
    try:
        connection.request("GET", url, headers=headers)
        response = connection.getresponse()
        return response.status, dict(response.getheaders()), response.read()
    finally:
        connection.close()


def test_with_editor_origins_each_answers_its_own_page_only_and_the_shared_origin_scripts_only() -> None:
    origins = EditorOrigins()
    with EditorServer(origins=origins) as server:
        shared = SHARED_ORIGIN
        editor, closed = origins.take(), origins.take()
        origins.release(closed, cleared=True)
        status, headers, page = _asked(server, f"{editor}/{EDITOR_PAGE}", {"Sec-Fetch-Site": "none"})
        assert status == 200 and headers["Cache-Control"] == "no-store"
        bundle = f"{shared}/{BUNDLE_FILE}?v={server.assets.script_versions[BUNDLE_FILE]}"
        assert f'<script src="{bundle}" crossorigin="anonymous"></script>' in page.decode()
        # Ours load from the shared origin too (cached from the second opening on), at their content's version.
        version = server.assets.script_versions["bridge.js"]
        assert f'<script src="{shared}/bridge.js?v={version}" crossorigin="anonymous"></script>' in page.decode()
        assert b'src="bridge.js"' not in page
        status, headers, script = _asked(server, f"{shared}/bridge.js?v={version}", {"Sec-Fetch-Dest": "script"})
        assert status == 200 and headers["Cache-Control"] == "max-age=86400"
        assert script == (server.assets.gui_dir / "bridge.js").read_bytes()
        assert _asked(server, f"{editor}/bridge.js", {"Sec-Fetch-Site": "same-origin"})[0] == 200
        for site in ("same-site", "cross-site"):  # a sibling editor's frame, window or fetch
            status, headers, _ = _asked(server, f"{editor}/{EDITOR_PAGE}", {"Sec-Fetch-Site": site})
            assert status == 403 and headers["Cache-Control"] == "no-store"  # not kept for the editor itself
        assert _asked(server, f"{editor}/{EDITOR_PAGE}", {})[0] == 403
        assert _asked(server, f"{closed}/{EDITOR_PAGE}", {"Sec-Fetch-Site": "none"})[0] == 403
        status, headers, _ = _asked(server, bundle, {"Sec-Fetch-Dest": "script"})
        assert status == 200 and headers["Access-Control-Allow-Origin"] == "*"
        assert _asked(server, bundle, {"Sec-Fetch-Dest": "iframe"})[0] == 403
        assert _asked(server, f"{shared}/bridge.js?v={version}", {"Sec-Fetch-Dest": "iframe"})[0] == 403
        assert _asked(server, f"{shared}/{EDITOR_PAGE}", {"Sec-Fetch-Dest": "script"})[0] == 403
        assert _asked(server, f"{shared}/{EDITOR_PAGE}", {"Sec-Fetch-Dest": "document"})[0] == 403
        assert f"GET {closed}/{EDITOR_PAGE}" in server.refusals.latest
        # The proxy's own address serves nothing to pages: the scripts are at the shared origin.
        assert _asked(server, f"{server.proxy}/bridge.js?v={version}", {"Sec-Fetch-Dest": "script"})[0] == 403


def test_the_shared_origin_answers_a_script_only_at_its_current_version() -> None:
    """A node's browsers share one cache (``_cache_template``): a script kept under a URL must be what the URL
    names, so nothing is kept under another version's URL or none, where a page could later find it."""
    with EditorServer(origins=EditorOrigins()) as server:
        versions = server.assets.script_versions
        assert {BUNDLE_FILE, "bridge.js", BARE_BUILT_FILES[0]} <= set(versions)  # installed scripts too
        script = {"Sec-Fetch-Dest": "script"}
        for url in (
            f"{SHARED_ORIGIN}/{BUNDLE_FILE}",
            f"{SHARED_ORIGIN}/{BUNDLE_FILE}?v=0000000000000000",
            f"{SHARED_ORIGIN}/{BUNDLE_FILE}?v={versions[BUNDLE_FILE]}&v=0000000000000000",
            f"{SHARED_ORIGIN}/static/blocks-media/default/green-flag.svg",  # installed, but no page script
        ):
            status, headers, _ = _asked(server, url, script)
            assert (status, headers["Cache-Control"]) == (403, "no-store"), url
        status, headers, body = _asked(server, f"{SHARED_ORIGIN}/{BUNDLE_FILE}?v={versions[BUNDLE_FILE]}", script)
        assert (status, headers["Cache-Control"]) == (200, "max-age=86400")
        assert body == (server.assets.dist_dir / BUNDLE_FILE).read_bytes()
