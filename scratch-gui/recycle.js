/*
 * Reusing an editor page for the next evaluation, safely.
 *
 * A fresh editor costs seconds of start-up, more than a whole evaluation in virtual time. Loading
 * a project already resets the VM the way Scratch itself does between projects (threads, targets,
 * clones, monitors, the timer, the answer, the pen layer), all but whether the last project was running
 * (announced stopped here). What is left is what an evaluation script can change in the page, and this
 * module handles it in two ways:
 * - undone here: listeners the script added to the VM, globals it defined, storage it wrote,
 *   mouse and keyboard state, turbo and compatibility mode, timers it left pending (these fire
 *   ahead of time, see clock.js), and functions it replaced on the VM, its renderer, sequencer,
 *   IO devices and targets (through the stage's prototypes), the block primitives, built-in objects
 *   and window (put back as they were);
 * - checked here: what could not be undone, intervals still running, and extensions, body nodes,
 *   cookies and runtime options that differ from the fresh page. Any difference is reported, and
 *   the page is closed instead of reused.
 * The snapshots are kept in this closure; only the list of differences leaves the page.
 */
(function () {
  'use strict';

  const BUILTINS = {
    Object, Function, Array, String, Number, Boolean, Symbol, BigInt, Promise, Map, Set, WeakMap, WeakSet,
    RegExp, Error, JSON, Math, Reflect, Date, Intl, ArrayBuffer, Uint8Array, Float32Array, TextEncoder,
    TextDecoder, EventTarget, Node, Element, HTMLElement, HTMLCanvasElement, Document, Event, KeyboardEvent,
    MouseEvent, console, performance,
  };
  const IO_DEVICES = ['clock', 'cloud', 'keyboard', 'mouse', 'mouseWheel', 'userData', 'video'];
  // Input devices whose plain state (numbers, flags, arrays) goes back to the fresh page's.
  const INPUT_DEVICES = ['clock', 'keyboard', 'mouse', 'mouseWheel', 'userData'];

  // Function-valued properties (and accessors) by "owner.name", with their owner and descriptor,
  // so that a replaced one can be put back.
  function functionsOf(label, object, into) {
    for (const name of Object.getOwnPropertyNames(object)) {
      const descriptor = Object.getOwnPropertyDescriptor(object, name);
      const parts = [descriptor.value, descriptor.get, descriptor.set].filter((part) => typeof part === 'function');
      if (parts.length > 0) into.set(`${label}.${name}`, {object, name, descriptor, parts});
    }
  }

  // An object and its prototypes up to Object.prototype (exclusive).
  function withPrototypes(label, object, into) {
    let current = object;
    let depth = 0;
    while (current && current !== Object.prototype) {
      functionsOf(depth === 0 ? label : `${label}${'.__proto__'.repeat(depth)}`, current, into);
      current = Object.getPrototypeOf(current);
      depth += 1;
    }
  }

  function patchableFunctions(vm) {
    const found = new Map();
    for (const [name, value] of Object.entries(BUILTINS)) {
      functionsOf(name, value, found);
      if (value.prototype) functionsOf(`${name}.prototype`, value.prototype, found);
    }
    functionsOf('window', window, found);
    const runtime = vm.runtime;
    withPrototypes('vm', vm, found);
    withPrototypes('runtime', runtime, found);
    withPrototypes('sequencer', runtime.sequencer, found);
    if (vm.renderer) withPrototypes('renderer', vm.renderer, found);
    const stage = runtime.getTargetForStage(); // its prototypes are every sprite's too
    if (stage) withPrototypes('stage', stage, found);
    for (const name of IO_DEVICES) if (runtime.ioDevices[name]) withPrototypes(`ioDevices.${name}`, runtime.ioDevices[name], found);
    functionsOf('primitives', runtime._primitives, found);
    return found;
  }

  // Listeners of the VM and the runtime by "owner event", with their emitter and event name.
  function listenersOf(vm) {
    const found = new Map();
    for (const [label, emitter] of [['vm', vm], ['runtime', vm.runtime]]) {
      for (const event of emitter.eventNames()) {
        found.set(`${label} ${String(event)}`, {emitter, event, listeners: emitter.listeners(event)});
      }
    }
    return found;
  }

  const loadedExtensions = (vm) => [...vm.extensionManager._loadedExtensions.keys()].sort().join();

  function deviceState(vm) {
    const state = {};
    for (const name of INPUT_DEVICES) {
      const device = vm.runtime.ioDevices[name];
      if (!device) continue;
      state[name] = Object.fromEntries(
        Object.entries(device).map(([key, value]) => [key, Array.isArray(value) ? [...value] : value]),
      );
    }
    return state;
  }

  function storageState(storage) {
    const state = new Map();
    for (let i = 0; i < storage.length; i += 1) state.set(storage.key(i), storage.getItem(storage.key(i)));
    return state;
  }

  let clean = null; // the fresh page
  let beforeScript = null; // the page with the project loaded, just before the script ran

  /** Record the fresh page, once it is ready. */
  function markClean(vm) {
    clean = {
      globals: new Set(Object.getOwnPropertyNames(window)),
      local: storageState(localStorage),
      session: storageState(sessionStorage),
      devices: deviceState(vm),
      turbo: vm.runtime.turboMode,
      compatibility: vm.runtime.compatibilityMode,
      options: JSON.stringify(vm.runtime.runtimeOptions),
      extensions: loadedExtensions(vm),
      body: bodyNodes(),
      cookie: document.cookie,
    };
  }

  /** Record the page as the script finds it; called right before an evaluation script runs. */
  function beforeEvaluation(vm) {
    beforeScript = {functions: patchableFunctions(vm), listeners: listenersOf(vm)};
  }

  const sameList = (a, b) => a.length === b.length && a.every((item, i) => item === b[i]);

  // Listeners added since `beforeScript` go; any other change is reported.
  function restoreListeners(vm, differences) {
    const listenersBefore = (key) => (beforeScript.listeners.get(key) || {listeners: []}).listeners;
    for (const [key, {emitter, event, listeners}] of listenersOf(vm)) {
      const before = listenersBefore(key);
      for (const listener of listeners) if (!before.includes(listener)) emitter.removeListener(event, listener);
    }
    const after = listenersOf(vm);
    for (const key of new Set([...after.keys(), ...beforeScript.listeners.keys()])) {
      const now = (after.get(key) || {listeners: []}).listeners;
      if (!sameList(now, listenersBefore(key))) differences.push(`listeners of ${key} changed`);
    }
  }

  function restoreGlobals(differences) {
    for (const name of Object.getOwnPropertyNames(window)) {
      if (clean.globals.has(name) || /^\d+$/.test(name)) continue;
      if (!Reflect.deleteProperty(window, name)) differences.push(`global ${name} cannot be removed`);
    }
    for (const name of clean.globals) if (!(name in window)) differences.push(`global ${name} was removed`);
  }

  function restoreStorage(storage, saved, label, differences) {
    for (const key of storageState(storage).keys()) if (!saved.has(key)) storage.removeItem(key);
    for (const [key, value] of saved) storage.setItem(key, value);
    if (storage.length !== saved.size) differences.push(`${label} cannot be restored`);
  }

  // Keys the device did not have go (the mouse has no position until a real mouse event).
  function restoreDevices(vm) {
    for (const [name, saved] of Object.entries(clean.devices)) {
      const device = vm.runtime.ioDevices[name];
      for (const key of Object.keys(device)) if (!(key in saved)) delete device[key];
      for (const [key, value] of Object.entries(saved)) {
        if (Array.isArray(value)) device[key] = [...value];
        else if (value === null || (typeof value !== 'object' && typeof value !== 'function')) device[key] = value;
      }
    }
  }

  // Functions the script replaced, added or removed are put back as they were before it ran.
  function restoreFunctions(vm, differences) {
    const now = patchableFunctions(vm);
    for (const [key, saved] of beforeScript.functions) {
      const current = now.get(key);
      if (current && sameList(current.parts, saved.parts)) continue;
      try {
        Object.defineProperty(saved.object, saved.name, saved.descriptor);
      } catch (e) {
        differences.push(`${key} was replaced and cannot be put back`);
      }
    }
    for (const [key, added] of now) {
      if (!beforeScript.functions.has(key) && !Reflect.deleteProperty(added.object, added.name)) {
        differences.push(`${key} was added and cannot be removed`);
      }
    }
  }

  // The GUI adds and removes a hidden sandbox iframe of its own (it processes costumes), so frames
  // (nodes and the window's index properties) do not count. Blockly makes its overlays (dropdown,
  // widget, tooltip) anew when the block editor is set up again: they count by their class.
  const isFrame = (node) => node.nodeName === 'IFRAME';
  const describeNode = (node) => {
    if (typeof node === 'string') return node;
    const className = typeof node.className === 'string' ? node.className.split(' ')[0] : '';
    return node.nodeName + (className ? '.' + className : '');
  };
  const isBlocklyOverlay = (node) => node.nodeName === 'DIV' && describeNode(node).startsWith('DIV.blockly');
  const bodyNodes = () => {
    const nodes = [...document.body.childNodes].filter((node) => !isFrame(node));
    const overlays = nodes.filter(isBlocklyOverlay).map(describeNode).sort();
    return [...nodes.filter((node) => !isBlocklyOverlay(node)), ...overlays];
  };

  function compareDom(differences) {
    const now = bodyNodes();
    if (!sameList(now, clean.body)) {
      const added = now.filter((node) => !clean.body.includes(node)).map((node) => '+' + describeNode(node));
      const gone = clean.body.filter((node) => !now.includes(node)).map((node) => '-' + describeNode(node));
      differences.push(`document.body has other child nodes (${[...added, ...gone].join(' ') || 'reordered'})`);
    }
    if (document.cookie !== clean.cookie) differences.push('document.cookie changed');
  }

  /**
   * Undo what the last evaluation left and compare the page with the fresh one; resolves to the
   * differences (empty: the page is as good as fresh once the next project is loaded).
   */
  async function recycle(vm, clock) {
    if (!clean || !beforeScript) return ['the page was not marked clean before its evaluation'];
    const differences = [];
    restoreFunctions(vm, []); // first, so that nothing below runs patched code; checked again at the end
    vm.runtime.stopAll();
    for (const left of await clock.drainEvaluation()) differences.push(`${left} is still pending`);
    vm.runtime.stopAll();
    restoreListeners(vm, differences);
    // The VM counts the scripts that ran in its last frame and announces a run when that count leaves 0.
    // A project stopped while running leaves it above 0 until the next frame, and loading a project
    // does not reset it: a green flag before any frame of the recycled page would go unannounced
    // (no PROJECT_RUN_START, the GUI's flag not lit). Announced now, as the next frame would.
    vm.runtime._emitProjectRunStatus(0);
    restoreGlobals(differences);
    restoreStorage(localStorage, clean.local, 'localStorage', differences);
    restoreStorage(sessionStorage, clean.session, 'sessionStorage', differences);
    restoreDevices(vm);
    if (vm.runtime.turboMode !== clean.turbo) vm.setTurboMode(clean.turbo);
    if (vm.runtime.compatibilityMode !== clean.compatibility) vm.setCompatibilityMode(clean.compatibility);
    if (JSON.stringify(vm.runtime.runtimeOptions) !== clean.options) differences.push('runtime options changed');
    const extensions = loadedExtensions(vm);
    if (extensions !== clean.extensions) differences.push(`extensions loaded: ${extensions}`);
    restoreFunctions(vm, differences);
    compareDom(differences);
    beforeScript = null;
    return differences;
  }

  window.__scratchworldRecycler = Object.freeze({markClean, beforeEvaluation, recycle});
})();
