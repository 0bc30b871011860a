"""Chromium's command line for a worker's browser: headless, offline but for the editor server (its proxy,
loopback included), and one merged list of feature switches, Playwright's and ours."""

from __future__ import annotations

CHROMIUM_ARGS: tuple[str, ...] = (
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    # A tile is drawn whole whenever part of it changes, so a screenshot is a function of what the page shows,
    # not of the order it was painted in: with partial raster, a recycled page (or one that started with an
    # empty stage) drew the tabs' rounded corners a shade off, 11-42 pixels, and the same agent saw other bytes.
    "--disable-partial-raster",
    # Without it the editor logs ~100 AudioContext warnings per page.
    "--autoplay-policy=no-user-gesture-required",
    # Offline here: every host but the loopback editor server fails to resolve, immediately.
    "--host-resolver-rules=MAP * ~NOTFOUND , EXCLUDE 127.0.0.1",
    # No UDP from pages (WebRTC would reach any port); what goes over TCP goes through the proxy.
    "--webrtc-ip-handling-policy=disable_non_proxied_udp",
)


def isolation_args(proxy: str) -> tuple[str, ...]:
    """Every request of every page goes to ``proxy`` (the editor server), loopback included."""
    return (f"--proxy-server={proxy}", "--proxy-bypass-list=<-loopback>")


PLAYWRIGHT_FEATURES_ENABLED = ("CDPScreenshotNewSurface", "SkipListAccountsWithoutGaiaCookies")
PLAYWRIGHT_FEATURES_DISABLED = (
    "AvoidUnnecessaryBeforeUnloadCheckSync",
    "DestroyProfileOnBrowserClose",
    "HttpsUpgrades",
    "HttpsFirstBalancedModeAutoEnable",
    "LensOverlay",
    "MediaRouter",
    "PaintHolding",
    "ThirdPartyStoragePartitioning",
    "AvoidCorsURLLoaderRestartOnRedirect",
    "TcpPortRandomizationWin",
    "OptimizationHints",
    "NetworkTimeServiceQuerying",
    "AimEnabled",
    "PreconnectToSearch",
    "msForceBrowserSignIn",
    "msEdgeUpdateLaunchServicesPreferredVersion",
)
"""Playwright's own feature switches (its ``chromiumSwitches.ts``, 1.65). Chromium keeps only the last
``--enable-features`` (and ``--disable-features``), and ours come after Playwright's, so ours carry both;
a test reads the real command line and fails when a Playwright upgrade changes its lists."""

FEATURES_ENABLED = ("EnablePortBoundCookies", "EnableSchemeBoundCookies")
"""Cookies bound to the origin's port and scheme: without them a cookie set at one editor origin
(127.0.0.2:<port>) is sent to every other one."""


FEATURES_DISABLED = ("WebUIOmniboxPopup", "WebUIOmniboxAimPopup", "IsolateSandboxedIframes")
"""Processes an editor never uses. Each page's window preloads the address bar's popups as WebUI pages, in
renderers of their own, though headless shows no address bar; and the editor's SVG-import sandbox (a
``sandbox="allow-scripts"`` iframe, opaque origin either way) gets a renderer of its own. Measured with 4-6
waiting editors (``/usr/bin/chromium`` 156): 200-211 MB per editor with them, 153-177 MB without, and 2.5
renderers per editor instead of 1.3. The sandbox keeps its opaque origin in the page's process; the browser
stays confined by its proxy and resolver rules either way."""


def feature_args(extra_args: tuple[str, ...] = ()) -> tuple[str, ...]:
    """One ``--enable-features`` and one ``--disable-features`` switch: Playwright's, ours and any in ``extra_args``."""
    enabled = [*PLAYWRIGHT_FEATURES_ENABLED, *FEATURES_ENABLED]
    disabled = [*PLAYWRIGHT_FEATURES_DISABLED, *FEATURES_DISABLED]
    for arg in extra_args:
        for switch, features in (("--enable-features=", enabled), ("--disable-features=", disabled)):
            if arg.startswith(switch):
                features += [name for name in arg.removeprefix(switch).split(",") if name]
    return (
        "--enable-features=" + ",".join(dict.fromkeys(enabled)),
        "--disable-features=" + ",".join(dict.fromkeys(disabled)),
    )


def launch_args(proxy: str, extra_args: tuple[str, ...] = ()) -> list[str]:
    """Chromium's switches after Playwright's: ours, the proxy, ``extra_args`` and the merged feature switches last."""
    features = ("--enable-features=", "--disable-features=")
    rest = [arg for arg in extra_args if not arg.startswith(features)]
    return [*CHROMIUM_ARGS, *isolation_args(proxy), *rest, *feature_args(extra_args)]
