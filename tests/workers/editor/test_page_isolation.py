"""A page reaches nothing but the editor's own files: not from a task's script, a project, or an agent's clicks.

A listener on another 127.0.0.1 port stands for what a cluster node keeps on loopback (Ray's GCS
and dashboard, a local model server). The browser here resolves the Scratch web services (and
Scratch Link's device manager, which public DNS really points at 127.0.0.1) to that listener, so
that every way out a page has would arrive there. The listener must see nothing, while the
editor server's log of refused requests shows each attempt was made and stopped at the boundary.
"""

from __future__ import annotations

import asyncio
import copy
import hashlib
import io
import json
import zipfile
from collections.abc import AsyncIterator, Callable, Iterator

import pytest

from tests.support.loopback import LoopbackListener
from tests.support.projects import counter_project
from workers.contract import EvaluationSpec, ObservationSettings, PrimitiveObservation, primitive_action
from workers.editor import BrowserConfig, BrowserSession
from workers.evaluation import Evaluator
from workers.kinds.tasks import PrimitiveEnvironment
from workers.primitive import PrimitiveObserver

WEB_SERVICES = (
    "device-manager.scratch.mit.edu",
    "translate-service.scratch.mit.edu",
    "synthesis-service.scratch.mit.edu",
)

pytestmark = pytest.mark.browser

EVERY_WAY_OUT = """
module.exports = async (vm, config) => {
  const base = `http://127.0.0.1:${config.port}`;
  const settle = (attempt) => Promise.race([
    attempt().catch((e) => 'threw ' + e.name),
    new Promise((resolve) => setTimeout(() => resolve('no answer in 10 s'), 10000)),
  ]);
  const element = (tag, attributes, parent) => new Promise((resolve) => {
    const node = document.createElement(tag);
    node.onload = () => resolve('load');
    node.onerror = () => resolve('error');
    Object.assign(node, attributes);
    (parent || document.body).appendChild(node);
  });
  const attempts = {
    fetch: () => fetch(`${base}/fetch`).then((r) => 'status ' + r.status),
    fetch_localhost: () => fetch(`http://localhost:${config.port}/fetch-localhost`).then((r) => 'status ' + r.status),
    xhr: () => new Promise((resolve) => {
      const request = new XMLHttpRequest();
      request.open('GET', `${base}/xhr`);
      request.onload = () => resolve('status ' + request.status);
      request.onerror = () => resolve('error');
      request.send();
    }),
    websocket: () => new Promise((resolve) => {
      const socket = new WebSocket(`ws://127.0.0.1:${config.port}/websocket`);
      socket.onopen = () => resolve('open');
      socket.onerror = () => resolve('error');
    }),
    image: () => element('img', {src: `${base}/image.png`}),
    script: () => element('script', {src: `${base}/script.js`}, document.head),
    stylesheet: () => element('link', {rel: 'stylesheet', href: `${base}/style.css`}, document.head),
    iframe: () => element('iframe', {src: `${base}/iframe`}),
    event_source: () => new Promise((resolve) => {
      const source = new EventSource(`${base}/event-source`);
      source.onopen = () => resolve('open');
      source.onerror = () => { source.close(); resolve('error'); };
    }),
    worker_fetch: () => new Promise((resolve) => {
      const code = `fetch('${base}/worker-fetch').then(() => postMessage('load'), () => postMessage('error'))`;
      const worker = new Worker(URL.createObjectURL(new Blob([code], {type: 'text/javascript'})));
      worker.onmessage = (event) => resolve(event.data);
      worker.onerror = () => resolve('worker error');
    }),
    module_import: () => import(`${base}/module.js`).then(() => 'load'),
    beacon: async () => (navigator.sendBeacon(`${base}/beacon`, 'x') ? 'queued' : 'refused'),
    webrtc: () => new Promise((resolve) => {
      const peer = new RTCPeerConnection({iceServers: [{urls: `stun:127.0.0.1:${config.port}`}]});
      peer.createDataChannel('x');
      peer.onicegatheringstatechange = () => {
        if (peer.iceGatheringState === 'complete') { peer.close(); resolve('gathered'); }
      };
      peer.createOffer().then((offer) => peer.setLocalDescription(offer));
    }),
  };
  const details = [];
  for (const [name, attempt] of Object.entries(attempts)) {
    details.push({name, passed: true, meta: await settle(attempt)});
  }
  return {passed_tests: details.length, total_tests: details.length, details};
};
"""

SAY_AND_SPEAK = """
module.exports = async (vm) => {
  const said = [];
  vm.runtime.on('SAY', (target, type, text) => said.push(String(text)));
  vm.greenFlag();
  const deadline = Date.now() + 20000;
  while (said.length === 0 && Date.now() < deadline) await new Promise((r) => setTimeout(r, 20));
  while (vm.runtime.threads.length > 0 && Date.now() < deadline) await new Promise((r) => setTimeout(r, 20));
  return {passed_tests: 1, total_tests: 1, details: [{name: 'the script ran', passed: said.length > 0, meta: said}]};
};
"""

_SVG = """<svg xmlns="http://www.w3.org/2000/svg" width="40" height="40">
<style>@import url({base}/svg-import.css); @font-face {{font-family: f; src: url({base}/svg-font.woff);}}</style>
<image href="{base}/svg-image.png" width="10" height="10"/><text font-family="f">hi</text></svg>"""


def hostile_project(port: int) -> bytes:
    """A project that asks for the network every way a project can: web-service blocks on the green
    flag (translate, text to speech), an SVG costume with external references, a custom extension URL."""
    base = f"http://127.0.0.1:{port}"
    archive = zipfile.ZipFile(io.BytesIO(counter_project().to_sb3()))
    project = json.loads(archive.read("project.json"))
    svg = _SVG.format(base=base).encode()
    svg_id = hashlib.md5(svg).hexdigest()
    sprite = project["targets"][1]
    costume = {"name": "remote", "assetId": svg_id, "md5ext": f"{svg_id}.svg", "dataFormat": "svg"}
    sprite["costumes"].insert(0, {**costume, "rotationCenterX": 20, "rotationCenterY": 20})
    sprite["currentCostume"] = 0
    sprite["blocks"] = {
        "flag": _block("event_whenflagclicked", next="say", top=True),
        "say": _block("looks_say", parent="flag", next="speak", inputs={"MESSAGE": [3, "translate", [10, ""]]}),
        "translate": _block(
            "translate_getTranslate", parent="say", inputs={"WORDS": [1, [10, "hello"]], "LANGUAGE": [1, "language"]}
        ),
        "language": _block("translate_menu_languages", parent="translate", fields={"languages": ["es", None]}),
        "speak": _block("text2speech_speakAndWait", parent="say", inputs={"WORDS": [1, [10, "hello"]]}),
    }
    project["extensions"] = ["translate", "text2speech", "remote"]
    project["extensionURLs"] = {"remote": f"{base}/extension.js"}
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w") as rebuilt:
        for name in archive.namelist():
            if name != "project.json":
                rebuilt.writestr(name, archive.read(name))
        rebuilt.writestr(f"{svg_id}.svg", svg)
        rebuilt.writestr("project.json", json.dumps(project))
    return out.getvalue()


def _block(
    opcode: str,
    *,
    parent: str | None = None,
    next: str | None = None,
    top: bool = False,
    inputs: dict | None = None,
    fields: dict | None = None,
) -> dict:
    block = {"opcode": opcode, "next": next, "parent": parent, "inputs": copy.deepcopy(inputs or {})}
    block.update(fields=fields or {}, shadow=opcode.endswith("_menu_languages"), topLevel=top)
    return {**block, "x": 0, "y": 0} if top else block


@pytest.fixture
def listener() -> Iterator[LoopbackListener]:
    """A fresh listener per test, so each test's count is its own."""
    with LoopbackListener() as running:
        yield running


@pytest.fixture
async def session(listener: LoopbackListener) -> AsyncIterator[BrowserSession]:
    """A browser whose host names resolve as if the Scratch services ran on this node's loopback."""
    mapped = ", ".join(f"MAP {host} 127.0.0.1:{listener.port}" for host in WEB_SERVICES)
    config = BrowserConfig(extra_args=(f"--host-resolver-rules={mapped}, MAP * ~NOTFOUND , EXCLUDE 127.0.0.1",))
    async with BrowserSession(config) as browser:
        yield browser


async def refused(session: BrowserSession, listener: LoopbackListener, wanted: Callable[[list[str]], bool]) -> None:
    """Wait (bounded: 60 s, for a loaded machine) until the refusals show the attempts, or something
    reached the listener."""
    for _ in range(1200):
        if wanted(session.refused_requests) or listener.connections or listener.datagrams:
            return
        await asyncio.sleep(0.05)


async def test_a_tasks_evaluation_script_reaches_nothing(session: BrowserSession, listener: LoopbackListener) -> None:
    spec = EvaluationSpec(
        script_name="ways_out.js", script_source=EVERY_WAY_OUT, timeout_s=60, config={"port": listener.port}
    )
    result = await Evaluator(session).evaluate(counter_project().to_sb3(), spec)
    assert result.error is None, result.error
    outcomes = {test.name: test.meta for test in result.tests}
    assert len(outcomes) == 13 and "no answer in 10 s" not in outcomes.values(), outcomes
    base = f"http://127.0.0.1:{listener.port}"
    expected = {f"GET {base}/{path}" for path in ("fetch", "xhr", "image.png", "script.js", "style.css", "iframe")}
    expected |= {f"GET {base}/{p}" for p in ("event-source", "worker-fetch", "module.js")}
    expected |= {f"GET http://localhost:{listener.port}/fetch-localhost", f"CONNECT 127.0.0.1:{listener.port}"}
    expected.add(f"POST {base}/beacon")
    await refused(session, listener, lambda seen: expected <= set(seen))
    assert listener.connections == [] and listener.datagrams == []  # not a byte, TCP or UDP (WebRTC's STUN)
    assert expected <= set(session.refused_requests), session.refused_requests
    assert outcomes["fetch"] == "threw TypeError" and outcomes["websocket"] == "error"


async def test_a_project_reaches_nothing(session: BrowserSession, listener: LoopbackListener) -> None:
    spec = EvaluationSpec(script_name="say_and_speak.js", script_source=SAY_AND_SPEAK, timeout_s=60)
    result = await Evaluator(session).evaluate(hostile_project(listener.port), spec)
    assert result.error is None and result.success, result  # the blocks ran, without their services
    services = {"CONNECT translate-service.scratch.mit.edu:443", "CONNECT synthesis-service.scratch.mit.edu:443"}
    await refused(session, listener, lambda seen: services <= set(seen))
    assert listener.connections == [] and listener.datagrams == []
    assert services <= set(session.refused_requests), session.refused_requests


async def settled_observation(environment: PrimitiveEnvironment) -> PrimitiveObservation:
    """An observation of a page at rest: on a loaded CI machine the extension library can still be
    laying out after the settle rule's bound, and a click at a moving item's centre may miss it."""
    for _ in range(30):
        observation = await environment.observe()
        if observation.settled:
            return observation
    raise AssertionError(f"the page never settled: {observation.warnings}")


async def test_an_agents_clicks_reach_nothing(session: BrowserSession, listener: LoopbackListener) -> None:
    """Two clicks add the micro:bit extension, whose page then calls Scratch Link on loopback."""
    async with session.editor() as editor:
        environment = PrimitiveEnvironment(editor, PrimitiveObserver(ObservationSettings(ocr="none"), None))
        for label in ("Add Extension", "micro:bit"):
            observation = await settled_observation(environment)
            index = next(e.index for e in observation.elements if e.text.startswith(label))
            envelope = await environment.execute(primitive_action({"api": "click", "args": {"index": index}}))
            assert envelope.success, envelope
        link = {"CONNECT device-manager.scratch.mit.edu:20110", "CONNECT 127.0.0.1:20111"}
        await refused(session, listener, lambda seen: link <= set(seen))
    assert listener.connections == [] and listener.datagrams == []
    assert link <= set(session.refused_requests), session.refused_requests
