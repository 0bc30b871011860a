/*
 * When the page has settled after a gesture: the one rule for every agent, scripted or not.
 *
 * Settled means two animation frames in a row with no DOM mutation (monitors and mirrored VM
 * values aside) and nothing under way: no gesture or drag, no palette scroll animation, no bump
 * of neighbouring blocks (Blockly bumps `bumpDelay` ms after a drop), no finite CSS animation,
 * and the workspace showing exactly the editing target's scripts. A screenshot taken then shows
 * the result of the last action rather than a frame of it, and the next gesture is planned on
 * geometry that will not move. `primitiveSettle` is the bridge function; `geometryWait` waits
 * for the same rule as its `quiet` condition.
 */
scratchworldModule({name: 'settle', requires: ['blockly'], create(ctx, blockly) {
  'use strict';

  const DEFAULT_MS = 2000;
  const MAX_MS = 30000;
  const QUIET_FRAMES = 2;
  // A frame that never comes (hidden page) must not hang the wait.
  const FRAME_FALLBACK_MS = 100;
  const MONITORS = '[class*="monitor-list_monitor-list"]';

  let watchedWorkspace = null;
  let lastMoveAt = -Infinity;

  // Remember when blocks last moved (bumps follow a drop); from the first look at the page on.
  function watch(state) {
    if (!state || watchedWorkspace === state.ws) return;
    watchedWorkspace = state.ws;
    const Events = state.SB.Events || {};
    state.ws.addChangeListener((event) => {
      if (event.type === Events.BLOCK_MOVE || event.type === Events.BLOCK_DRAG) lastMoveAt = performance.now();
    });
  }

  // Why the page is not settled yet, or null.
  function busy() {
    const state = blockly.drawn();
    watch(state);
    if (state) {
      if (state.ws.currentGesture_ || (state.ws.isDragging && state.ws.isDragging())) return 'gesture';
      if (state.flyoutWs && state.flyoutWs.currentGesture_) return 'gesture';
      if (state.flyout && state.flyout.scrollTarget !== undefined && state.flyout.scrollTarget !== null) return 'flyout scroll';
      // Bumps are timers of the page clock. On an episode's paused virtual clock no page time passes
      // before the next action, so none can come sooner, and waiting for one would never end.
      const bumpDelay = (state.SB.config && state.SB.config.bumpDelay) || 0;
      if (!ctx.pageTimeStands() && performance.now() - lastMoveAt < bumpDelay) return 'bump';
      if (!blockly.inSync()) return 'workspace out of sync with the VM';
    }
    for (const animation of document.getAnimations()) {
      if (animation.playState !== 'running' || !animation.effect) continue;
      if (Number.isFinite(animation.effect.getComputedTiming().endTime)) return 'animation';
    }
    return null;
  }

  function ignored(record) {
    const target = record.target.nodeType === Node.ELEMENT_NODE ? record.target : record.target.parentElement;
    if (!target) return false;
    // Controlled inputs mirror VM state (sprite x/y) into their value attribute; monitors
    // follow a running project. Neither is the result of an agent's action.
    if (record.type === 'attributes' && record.attributeName === 'value' && target.tagName === 'INPUT') return true;
    return !!target.closest(MONITORS);
  }

  function nextFrame() {
    // Real time: on an episode's paused virtual clock a virtual timer would not fire.
    return Promise.race([new Promise((resolve) => requestAnimationFrame(() => resolve())), ctx.realSleep(FRAME_FALLBACK_MS)]);
  }

  // Waits (at most `maxMs` of real time) for the page to settle: {settled, waitedMs, busy?}.
  async function settle(maxMs) {
    const started = ctx.realNow();
    let dirty = false;
    const observer = new MutationObserver((records) => {
      if (!dirty && records.some((r) => !ignored(r))) dirty = true;
    });
    observer.observe(document.body, {subtree: true, attributes: true, childList: true, characterData: true});
    let quiet = 0;
    try {
      for (;;) {
        await nextFrame();
        const reason = busy();
        quiet = dirty || reason ? 0 : quiet + 1;
        dirty = false;
        const waited = ctx.realNow() - started;
        if (quiet >= QUIET_FRAMES) return {settled: true, waitedMs: Math.round(waited)};
        if (waited >= maxMs) return {settled: false, waitedMs: Math.round(waited), busy: reason || 'dom mutations'};
      }
    } finally {
      observer.disconnect();
    }
  }

  function checkedMaxMs(value) {
    const maxMs = value == null ? DEFAULT_MS : Number(value);
    if (!(maxMs >= 0) || maxMs > MAX_MS) {
      throw new ctx.BridgeFailure('bad_request', `maxMs must be a number from 0 to ${MAX_MS}`);
    }
    return maxMs;
  }

  return {
    watch: watch,
    busy: busy,
    settle: settle,
    MAX_MS: MAX_MS,
    api: {primitiveSettle: (args) => settle(checkedMaxMs(args.maxMs))},
  };
}});
