"""Editor origins are handed out in port order, never twice at once, and never again uncleared; the switches
Chromium is launched with carry one merged feature list; the isolation is a node setting."""

from __future__ import annotations

import pytest

from workers.editor import BrowserConfig
from workers.editor._browser import ISOLATION_ENV
from workers.editor._origins import EditorOrigins, OriginsExhaustedError
from workers.editor._switches import (
    FEATURES_DISABLED,
    FEATURES_ENABLED,
    PLAYWRIGHT_FEATURES_DISABLED,
    PLAYWRIGHT_FEATURES_ENABLED,
    launch_args,
)


def test_origins_wrap_only_past_cleared_ports_and_skip_live_and_retired_ones() -> None:
    origins = EditorOrigins(first=20000, last=20002)
    first, second, third = origins.take(), origins.take(), origins.take()
    assert (first, second, third) == ("http://127.0.0.2:20000", "http://127.0.0.2:20001", "http://127.0.0.2:20002")
    assert origins.is_live("127.0.0.2:20001") and not origins.is_live("127.0.0.1:20001")
    with pytest.raises(OriginsExhaustedError):
        origins.take()
    origins.release(second, cleared=True)
    origins.release(first, cleared=False)  # its storage could not be cleared
    assert not origins.is_live("127.0.0.2:20001")
    assert origins.take() == second  # wrapped, past the live 20002 and the retired 20000
    origins.release(third, cleared=True)
    assert origins.take() == third
    with pytest.raises(OriginsExhaustedError):
        origins.take()


def test_our_feature_switches_come_last_and_carry_playwrights_and_any_extra_ones() -> None:
    args = launch_args("http://127.0.0.1:1", ("--enable-features=Extra", "--mute-audio", "--disable-features=Off"))
    assert "--mute-audio" in args
    enabled = [a for a in args if a.startswith("--enable-features=")]
    disabled = [a for a in args if a.startswith("--disable-features=")]
    assert enabled == [f"--enable-features={','.join((*PLAYWRIGHT_FEATURES_ENABLED, *FEATURES_ENABLED, 'Extra'))}"]
    assert disabled == [f"--disable-features={','.join((*PLAYWRIGHT_FEATURES_DISABLED, *FEATURES_DISABLED, 'Off'))}"]
    assert args[-2:] == [*enabled, *disabled]


def test_the_isolation_is_the_nodes_setting_and_a_bad_one_is_named(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv(ISOLATION_ENV, raising=False)
    assert BrowserConfig().editor_isolation == "origin"
    monkeypatch.setenv(ISOLATION_ENV, "context")
    assert BrowserConfig().editor_isolation == "context"
    monkeypatch.setenv(ISOLATION_ENV, "tabs")
    with pytest.raises(ValueError, match="SCRATCHWORLD_EDITOR_ISOLATION must be origin or context, not 'tabs'"):
        BrowserConfig()
