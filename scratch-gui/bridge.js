/*
 * The bridge: the one namespace (`window.scratchworld`) through which Python drives the editor.
 *
 * Python only ever runs `scratchworld.call(name, args)` with JSON arguments and gets back a JSON
 * envelope `{ok: true, value}` or `{ok: false, error: {kind, message}}`, so no JavaScript is ever
 * assembled from strings on the Python side and every failure arrives as data, not as a
 * Playwright exception whose text would have to be parsed.
 */
(function () {
  'use strict';

  let vm = null;
  let store = null;
  let bareStage = null; // the bare page's stage (bare/stage.js); null on the editor page
  let projectLoads = 0;
  const projectLoadedHooks = []; // feature modules' state that belongs to one project
  const evaluationObservers = []; // feature modules that watch a script's run (trace/record.js)
  const runners = new Map(); // feature modules' own scripts, run in place of a task's (explore/run.js)

  // The page clock (clock.js, loaded first): real time except while an evaluation runs virtually,
  // or an agent's page runs an episode on the paused virtual clock.
  const clock = window.__scratchworldClock;
  delete window.__scratchworldClock;
  const CLOCKS = ['virtual', 'real'];
  // Seeded `Math.random` for perturbed evaluations (random.js).
  const random = window.__scratchworldRandom;
  delete window.__scratchworldRandom;
  const RENDERS = ['on_demand', 'every_frame'];
  // Undoing and checking what an evaluation leaves, so that the page can serve the next one.
  const recycler = window.__scratchworldRecycler;
  delete window.__scratchworldRecycler;
  // Resetting and checking the editor's own UI state (menus, modals, tabs, palette...), after an episode.
  // The bare evaluation page (bare.html) has no editor UI, so nothing to reset there.
  const NO_GUI = {markClean() {}, showTargetPosition() {}, reset: async () => [], compare: () => []};
  const guiState = window.__scratchworldGuiState || NO_GUI;
  delete window.__scratchworldGuiState;
  // The page's AudioContexts, suspended while no one hears them (audio.js).
  const audio = window.__scratchworldAudio.create(() => vm, () => blocksComponent());
  delete window.__scratchworldAudio;
  // The palette, held empty until its first use (first-palette.js; the bare page has none).
  const firstPalette = window.__scratchworldFirstPalette ||
    {hold() {}, waiting: () => false, isHeld: () => false, stopHolding() {}, release: () => false};
  delete window.__scratchworldFirstPalette;
  // An empty default project for an editor opened ahead (empty-start.js; the bare page has no GUI).
  const emptyStart = window.__scratchworldEmptyStart || {replaceDefault: () => false};
  delete window.__scratchworldEmptyStart;

  class BridgeFailure extends Error {
    constructor(kind, message) {
      super(message);
      this.kind = kind;
    }
  }

  // What a script threw, in at most 2000 characters (a script may throw megabytes).
  function describe(reason) {
    let text;
    if (reason instanceof Error) text = `${reason.name}: ${reason.message}`;
    else if (typeof reason === 'string') text = reason;
    else {
      try {
        text = JSON.stringify(reason);
      } catch (e) {
        text = 'an unprintable value';
      }
    }
    return String(text).slice(0, 2000);
  }

  function requireVm() {
    if (!vm) throw new BridgeFailure('editor_not_ready', 'the editor has not handed over its VM yet');
    return vm;
  }

  function rendererName(renderer) {
    try {
      const gl = renderer.gl;
      const info = gl.getExtension('WEBGL_debug_renderer_info');
      return String(gl.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : gl.RENDERER));
    } catch (e) {
      return null;
    }
  }

  // The palette's flyout holds rendered blocks only once Blockly has drawn the workspace (and the
  // project's palette: the first one, first-palette.js, has only the categories' labels).
  function workspaceRendered() {
    return !!document.querySelector('.blocklyFlyout .blocklyBlockCanvas > g.blocklyBlock');
  }

  // Ready for use, apart from the renderer, which Python checks separately to fail with a
  // specific error instead of waiting for something that will never come. The bare page has no
  // workspace and no default project: its VM is all there is. While the palette is held, the GUI
  // must have caught up with the toolbox it last sent (drawn with empty categories).
  function settled() {
    if (bareStage) return !!vm;
    if (!vm || projectLoads < 1) return false;
    return firstPalette.isHeld() ? firstPalette.waiting() && paletteCaughtUp() : workspaceRendered();
  }

  function paletteCaughtUp() {
    if (!document.querySelector('.blocklyFlyout')) return false;
    try {
      return blocksComponent()._renderedToolboxXML === store.getState().scratchGui.toolbox.toolboxXML;
    } catch (e) {
      return false; // the workspace is not rendered yet
    }
  }

  // Draw the default project's palette held since the opening; the page is settled again once it is drawn.
  function drawPalette() {
    if (bareStage) throw new BridgeFailure('bad_request', 'the bare page has no palette');
    return {released: firstPalette.release()};
  }

  function status() {
    const renderer = vm ? vm.renderer : null;
    const canvas = renderer && renderer.gl ? renderer.gl.canvas : null;
    return {
      page: bareStage ? 'bare' : 'editor',
      vm: !!vm,
      workspace: workspaceRendered(),
      projectLoads: projectLoads,
      renderer: !!renderer,
      rendererName: renderer ? rendererName(renderer) : null,
      stageCanvas: canvas ? [canvas.width, canvas.height] : null,
      devicePixelRatio: window.devicePixelRatio,
      // The VM knows no mouse position until a real mouse event reached the stage.
      mouseKnown: !!vm && typeof vm.runtime.ioDevices.mouse._scratchX === 'number',
      loadingState: store ? String(store.getState().scratchGui.projectState.loadingState) : null,
      // A page waiting for use steps no VM and keeps its audio suspended (audio.js).
      stepping: !!vm && vm.runtime._steppingInterval !== null,
      audio: audio.vmContext() ? audio.vmContext().state : null,
      workspaceAudio: audio.workspaceContexts().map((context) => context.state),
      otherAudio: audio.otherContexts().map((context) => context.state),
    };
  }

  function decodeBase64(text) {
    if (typeof text !== 'string') throw new BridgeFailure('bad_request', 'sb3Base64 must be a string');
    if (Uint8Array.fromBase64) return Uint8Array.fromBase64(text);
    const raw = atob(text);
    const bytes = new Uint8Array(raw.length);
    for (let i = 0; i < raw.length; i++) bytes[i] = raw.charCodeAt(i);
    return bytes;
  }

  function encodeBase64(bytes) {
    if (bytes.toBase64) return bytes.toBase64();
    let raw = '';
    for (let i = 0; i < bytes.length; i += 0x8000) {
      raw += String.fromCharCode.apply(null, bytes.subarray(i, i + 0x8000));
    }
    return btoa(raw);
  }

  // Canvas sizes of the GUI's stage modes at device pixel ratio 1 and a window of at least 1096 px.
  const STAGE_CANVAS = {small: [240, 180], large: [480, 360]};
  const STAGE_WAIT_MS = 5000;

  // Switch the GUI's stage size (as the "small stage" button does) and wait until the renderer's
  // canvas has the new size: evaluation helpers read the canvas to find the stage edges.
  async function setStageSize(args) {
    const size = args.size;
    if (!Object.prototype.hasOwnProperty.call(STAGE_CANVAS, size)) {
      throw new BridgeFailure('bad_request', 'size must be "small" or "large"');
    }
    const theVm = requireVm();
    if (bareStage) return bareStage.setSize(...STAGE_CANVAS[size]); // sized at once, as the GUI's stage ends up
    if (!store) throw new BridgeFailure('editor_not_ready', 'the GUI store is not attached');
    store.dispatch({type: 'scratch-gui/StageSize/SET_STAGE_SIZE', stageSize: size});
    const canvas = theVm.renderer.gl.canvas;
    const [width, height] = STAGE_CANVAS[size];
    const deadline = performance.now() + STAGE_WAIT_MS;
    while (canvas.width !== width || canvas.height !== height) {
      if (performance.now() > deadline) {
        throw new BridgeFailure('bridge_error', `the ${size} stage canvas is ${canvas.width}x${canvas.height}, expected ${width}x${height} (window size or pixel ratio changed?)`);
      }
      await new Promise((resolve) => requestAnimationFrame(resolve));
    }
    const rect = canvas.getBoundingClientRect();
    return {canvas: [canvas.width, canvas.height], stageRect: {x: rect.x, y: rect.y, width: rect.width, height: rect.height}};
  }

  async function loadProject(args) {
    const theVm = requireVm();
    const bytes = decodeBase64(args.sb3Base64);
    firstPalette.stopHolding(); // the project's own palette is the first one drawn
    try {
      await theVm.loadProject(bytes.buffer);
    } catch (reason) {
      throw new BridgeFailure('project_invalid', `the VM refused the project: ${describe(reason)}`);
    }
    recycler.beforeEvaluation(theVm); // what an agent's page is compared with when it is recycled
    guiState.showTargetPosition(gui());
    for (const hook of projectLoadedHooks) hook();
    return {targets: theVm.runtime.targets.filter(t => t.isOriginal).map(t => t.getName())};
  }

  async function saveProject() {
    const blob = await requireVm().saveProjectSb3();
    const bytes = new Uint8Array(await blob.arrayBuffer());
    return {sb3Base64: encodeBase64(bytes), size: bytes.length};
  }

  async function evaluate(args) {
    const theVm = requireVm();
    const timeoutMs = Number(args.timeoutMs);
    if (!(timeoutMs > 0)) throw new BridgeFailure('bad_request', 'timeoutMs must be a positive number');
    const clockMode = args.clock || 'real';
    if (!CLOCKS.includes(clockMode)) throw new BridgeFailure('bad_request', 'clock must be "virtual" or "real"');
    const render = args.render || 'every_frame';
    if (!RENDERS.includes(render)) throw new BridgeFailure('bad_request', 'render must be "on_demand" or "every_frame"');
    const script = feature('evaluation/script');
    const perturbation = script.perturbationOf(args.perturbation, clockMode);
    const frameTiming = script.frameTimingOf(args.frameTiming, clockMode);
    // Each observer checks its arguments now, before anything starts: null, or its {start, stop}.
    const watches = evaluationObservers.map((observer) => observer(theVm, args)).filter(Boolean);
    const helperGlobal = args.helperGlobal || 'EvaluationUtils';
    if (!/^[A-Za-z_$][\w$]*$/.test(helperGlobal)) {
      throw new BridgeFailure('bad_request', 'helperGlobal must be a JavaScript identifier');
    }
    // A runner (`{name, args}`) is one of the page's own scripts (explore/run.js), run instead of the task's.
    const runner = args.runner == null ? null : runnerOf(args.runner);
    recycler.beforeEvaluation(theVm); // before the script's own top-level code runs
    clock.beginEvaluation();
    let helper = null;
    if (runner === null && args.helperSource != null) {
      helper = script.loadModule(args.helperSource, args.helperName || 'helper.js', null);
      window[helperGlobal] = helper;
    }
    const scriptName = runner !== null ? `runner ${args.runner.name}` : args.scriptName || 'evaluation.js';
    const run = runner !== null ? runner : script.loadModule(args.scriptSource, scriptName, helper);
    if (typeof run !== 'function') {
      throw new BridgeFailure('script_invalid', `${scriptName} must set module.exports to a function, got ${typeof run}`);
    }
    const cleanup = () => theVm.runtime.stopAll();
    const TIMED_OUT = {};
    let timer = null;
    // A perturbed run draws its random numbers from the recorded seed (and meets the VM's frame loop
    // at the given phase, and its timers come late as given: see clock.js).
    const undoRandom = perturbation ? random.seed(perturbation.randomSeed, theVm.runtime) : null;
    // Virtual from here: the script, the VM and the timeout below all run on the skipping clock,
    // so the timeout is a cap in simulated seconds.
    if (clockMode === 'virtual') {
      const late = perturbation ? {phaseMs: perturbation.phaseMs, lateness: perturbation.lateness} : {};
      clock.startVirtual({...late, frameTiming: frameTiming});
    }
    if (args.traceFrames) clock.traceFrames(); // every VM frame's time and work (benchmarks/frame_lateness.py)
    const undoRender = render === 'on_demand' ? feature('drawing').drawOnDemand(theVm.renderer) : null;
    const timedOut = new Promise((resolve) => {
      timer = setTimeout(() => resolve(TIMED_OUT), timeoutMs);
    });
    for (const watch of watches) watch.start(); // after the recycler's snapshot: what they patch is put back
    const started = performance.now();
    let outcome;
    let durationMs;
    let frames = null;
    const notes = {}; // what the watches report at their stop (evaluation/first-failure.js: earlyStop)
    try {
      outcome = await Promise.race([Promise.resolve().then(() => run(theVm, args.config || {}, cleanup)), timedOut]);
    } catch (reason) {
      throw new BridgeFailure('script_error', `${scriptName} failed: ${describe(reason)}`);
    } finally {
      clearTimeout(timer);
      // What the script saw, not what stopping the VM does; last started, first stopped (their hooks nest);
      // what a watch's stop returns (an object) joins evaluate's `notes`.
      for (const watch of watches.slice().reverse()) Object.assign(notes, watch.stop());
      try { theVm.runtime.stopAll(); } catch (e) { /* the verdict is already decided */ }
      durationMs = performance.now() - started;
      clock.stopVirtual();
      frames = clock.takeFrameTrace();
      if (undoRandom) undoRandom();
      if (undoRender) undoRender();
    }
    if (outcome === TIMED_OUT) {
      const unit = clockMode === 'virtual' ? 's of virtual time' : 's';
      throw new BridgeFailure('script_timeout', `${scriptName} did not finish within ${timeoutMs / 1000} ${unit}`);
    }
    return {resultJson: script.toJson(outcome, scriptName), durationMs: durationMs, frames: frames, notes: notes};
  }

  // The script a registered runner makes of its checked arguments (a BridgeFailure when they are bad).
  function runnerOf(value) {
    const name = value && value.name;
    if (!runners.has(name)) throw new BridgeFailure('bad_request', `unknown runner ${JSON.stringify(name)}`);
    return runners.get(name)(value.args == null ? {} : value.args);
  }

  const MAX_ADVANCE_MS = 10 * 60 * 1000;

  // An episode on the paused virtual clock: time moves only in `advanceClock`; its audio stands still.
  async function episodeClock(args) {
    if (!CLOCKS.includes(args.mode)) throw new BridgeFailure('bad_request', 'mode must be "virtual" or "real"');
    if (clock.status().mode === 'virtual') throw new BridgeFailure('bad_request', 'the clock is virtual already');
    if (args.mode === 'virtual') {
      clock.pauseVirtual();
      await audio.set(false);
    }
    return clock.status();
  }

  async function advanceClock(args) {
    const ms = Number(args.ms);
    if (!(ms >= 0 && ms <= MAX_ADVANCE_MS)) throw new BridgeFailure('bad_request', `ms must be from 0 to ${MAX_ADVANCE_MS}`);
    if (!clock.status().paused) throw new BridgeFailure('bad_request', 'the page is not on a paused virtual clock');
    const draw = args.draw === undefined ? true : args.draw;
    if (typeof draw !== 'boolean') throw new BridgeFailure('bad_request', 'draw must be true or false');
    // Nobody looks at the stage until the advance is over: its frames are drawn on demand, and the last
    // one once at the end (what the page shows afterwards is the same; a step costs a third less CPU).
    // `draw: false` leaves even that one to the next advance that draws: where nobody looks at the stage
    // afterwards (before an action, between a drag's moves, a composite agent's page), and a frame of the
    // software-WebGL stage costs the browser more than the step's own work.
    const drawn = feature('drawing').drawOnDemand(requireVm().renderer);
    try {
      await clock.advance(ms);
    } finally {
      drawn({draw: draw});
    }
    return {now: clock.now()};
  }

  function gui() {
    return {store: store, blocks: () => blocksComponent()};
  }

  // An episode's seeded `Math.random` (random.js): its undo, until the page is recycled.
  let episodeRandom = null;

  function seedRandom(args) {
    const seed = args.seed;
    if (!random.isSeed(seed)) throw new BridgeFailure('bad_request', 'seed must be an integer from 0 to 2^32 - 1');
    if (episodeRandom) episodeRandom();
    episodeRandom = random.seed(seed, requireVm().runtime);
    return {seed: seed};
  }

  async function recycle() {
    const theVm = requireVm();
    clock.stopVirtual(); // an episode's page may still be on its paused clock
    if (episodeRandom) {
      episodeRandom();
      episodeRandom = null;
    }
    const differences = await guiState.reset(gui());
    differences.push(...await recycler.recycle(theVm, clock));
    differences.push(...guiState.compare(gui()));
    if (differences.length === 0) await park(); // it waits for reuse
    return {differences: differences};
  }

  // A page waiting for use (opened ahead or recycled) steps no VM (about a third of a core) and
  // keeps its audio suspended; `resume` starts both when it is lent.
  async function park() {
    requireVm().quit();
    await audio.set(false);
  }

  const api = {
    status, setStageSize, drawPalette, loadProject, saveProject, evaluate, episodeClock, advanceClock, seedRandom,
    recycle,
    redrawPanels: () => { requireVm().emitTargetsUpdate(false); },
    clockStatus: () => clock.status(),
    markClean: () => {
      recycler.markClean(requireVm());
      guiState.markClean(gui());
    },
    park: park,
    resume: async () => { // a parked or recycled page runs again
      await audio.set(true);
      requireVm().start();
    },
  };

  // The GUI's Blocks component (it owns ScratchBlocks and the visible workspace), found once
  // through React's fiber tree from the workspace element, since the GUI exports no handle.
  let blocksComponentCache = null;
  function blocksComponent() {
    if (blocksComponentCache && blocksComponentCache.workspace) return blocksComponentCache;
    let node = document.querySelector('.blocklyWorkspace');
    while (node && !Object.keys(node).some((k) => k.startsWith('__reactFiber$'))) node = node.parentElement;
    let fiber = node && node[Object.keys(node).find((k) => k.startsWith('__reactFiber$'))];
    for (; fiber; fiber = fiber.return) {
      const state = fiber.stateNode;
      if (state && state.ScratchBlocks && state.workspace && typeof state.getToolboxXML === 'function') {
        blocksComponentCache = state;
        return state;
      }
    }
    throw new BridgeFailure('editor_not_ready', 'the block workspace is not rendered yet');
  }

  // Feature modules (modules.js registers them), created in dependency order; their `api`s join the table,
  // and the bridge's own functions use what some return (`feature`).
  const registry = window.__scratchworldModules;
  delete window.__scratchworldModules;
  delete window.scratchworldModule;
  const context = {
    requireVm: requireVm, BridgeFailure: BridgeFailure, describe: describe, blocksComponent: blocksComponent,
    isSeed: (value) => random.isSeed(value),
    realNow: () => clock.realNow(), realSleep: (ms) => clock.realSleep(ms),
    pageTimeStands: () => clock.status().paused, // an episode's virtual clock, between two advances
    onProjectLoaded: (hook) => projectLoadedHooks.push(hook),
    // (vm, evaluate's args) => null | {start, stop}; what stop returns (an object) joins evaluate's `notes`
    onEvaluation: (observer) => evaluationObservers.push(observer),
    // (name, (args) => script): `evaluate` with `runner: {name, args}` runs the script made, as it runs a task's.
    addRunner: (name, make) => {
      if (runners.has(name)) throw new Error(`runner ${name} registered twice`);
      runners.set(name, make);
    },
  };
  const created = registry ? registry.createAll(context) : new Map();
  function feature(name) {
    if (!created.has(name)) throw new BridgeFailure('bridge_error', `page module ${name} is not loaded: is it in the page?`);
    return created.get(name);
  }
  for (const instance of created.values()) {
    for (const [name, fn] of Object.entries(instance.api || {})) {
      if (Object.prototype.hasOwnProperty.call(api, name)) throw new Error(`bridge function ${name} registered twice`);
      api[name] = fn;
    }
  }

  async function call(name, args) {
    try {
      if (!Object.prototype.hasOwnProperty.call(api, name)) {
        throw new BridgeFailure('bad_request', `unknown bridge function ${JSON.stringify(name)}`);
      }
      return {ok: true, value: await api[name](args || {})};
    } catch (reason) {
      const kind = reason instanceof BridgeFailure ? reason.kind : 'bridge_error';
      return {ok: false, error: {kind: kind, message: reason instanceof BridgeFailure ? reason.message : describe(reason)}};
    }
  }

  // Read-only so that an evaluation script cannot replace the bridge Python relies on.
  Object.defineProperty(window, 'scratchworld', {
    value: Object.freeze({
      call: call,
      settled: settled,
      attachVm: (theVm) => { clock.attachVm(theVm); vm = theVm; },
      attachStorage: (storage) => { emptyStart.replaceDefault(storage); },
      attachStore: (theStore) => {
        store = theStore;
        firstPalette.hold(theStore);
      },
      // Only before the VM (bare/stage.js does so): a script that runs later cannot swap the stage.
      attachStage: (stage) => {
        if (vm) throw new Error('the stage must be attached before the VM');
        bareStage = stage;
      },
      noteProjectLoaded: () => { projectLoads += 1; },
    }),
    writable: false,
    configurable: false,
  });
})();
