/*
 * `geometryWait`: waits, bounded, for a named condition after a gesture (the palette finished its
 * scroll animation, a menu is open and still, a new block arrived in the VM, ...), so callers
 * never sleep for a fixed time. `quiet` is the page's one settle rule (shared/settle.js).
 */
scratchworldModule({name: 'geometry/waits', requires: ['blockly', 'settle', 'geometry/blocks', 'geometry/widgets', 'geometry/snapshot'], create(ctx, blockly, settle, blocks, widgets, snapshots) {
  'use strict';

  const fail = (message) => new ctx.BridgeFailure('bad_request', message);

  const DEFAULT_WAIT_MS = 5000;
  const POLL_MS = 10;
  // A rect or scroll position must be unchanged for this many polls to count as still.
  const STILL_POLLS = 2;

  // Each condition returns {done, value}; `still` conditions also need `value` to stay the same.
  const CONDITIONS = {
    flyoutSettled: {still: true, check: () => {
      const state = blocks.flyoutState();
      return {done: !state.animating, value: state.scrollY};
    }},
    editingTarget: {still: true, check: (args) => {
      const vm = ctx.requireVm();
      const name = vm.editingTarget ? vm.editingTarget.getName() : null;
      const state = blocks.flyoutState();
      return {done: name === args.name && blockly.inSync() && !state.animating, value: `${name}|${state.scrollY}`};
    }},
    menuOpen: {still: true, check: () => {
      const state = widgets.menu();
      // Still means placed (the div may animate in) and not scrolling (its items move).
      return {done: state.open, value: state.open ? JSON.stringify([state.rect, state.items.length ? state.items[0].rect : null]) : null};
    }},
    menuClosed: {still: false, check: () => ({done: !widgets.menu().open, value: null})},
    textEditorOpen: {still: false, check: () => {
      const state = widgets.textEditor();
      return {done: state.open && state.focused, value: null};
    }},
    textEditorShown: {still: false, check: () => ({done: widgets.textEditor().open, value: null})},
    textEditorClosed: {still: false, check: () => ({done: !widgets.textEditor().open, value: null})},
    colourPickerOpen: {still: true, check: () => {
      const state = widgets.colourPicker();
      return {done: state.open && state.sliders.length === 3, value: JSON.stringify(state.sliders.map((s) => s.rect))};
    }},
    colourPickerClosed: {still: false, check: () => ({done: !widgets.colourPicker().open, value: null})},
    modalOpen: {still: true, check: () => {
      const state = widgets.modal();
      return {done: state.open && state.inputs.length > 0, value: state.open ? JSON.stringify(state.inputs.map((i) => i.rect)) : null};
    }},
    modalClosed: {still: false, check: () => ({done: !widgets.modal().open, value: null})},
    // A new top-level block of `opcode` (not one of `known`) is in the VM and the workspace.
    newBlock: {still: false, check: (args) => {
      const known = new Set(args.known || []);
      const fresh = blockly.topBlocks().vm.filter((b) => b.opcode === args.opcode && !known.has(b.id));
      const ok = fresh.length === 1 && blockly.inSync();
      return {done: ok, value: ok ? fresh[0].id : fresh.map((b) => b.id)};
    }},
    inSync: {still: false, check: () => ({done: blockly.inSync(), value: null})},
    // The VM (which learns of edits asynchronously) holds `value` in a field or input of a block.
    blockValue: {still: false, check: (args) => {
      const values = blocks.blockFields({id: args.id})[args.kind] || {};
      return {done: values[args.name] === args.value, value: values[args.name] === undefined ? null : values[args.name]};
    }},
    snapshot: {still: false, check: (args) => {
      const current = snapshots.snapshot();
      return {done: !blockly.dragging() && JSON.stringify(current) === args.expected, value: current};
    }}
  };

  async function wait(args) {
    const timeoutMs = Math.min(Number(args.timeoutMs) || DEFAULT_WAIT_MS, settle.MAX_MS);
    if (args.until === 'quiet') {
      const result = await settle.settle(timeoutMs);
      return {ok: result.settled, value: result.settled ? null : result.busy, waitedMs: result.waitedMs};
    }
    const condition = CONDITIONS[args.until];
    if (!condition) {
      throw fail(`unknown condition ${JSON.stringify(args.until)}; conditions: quiet, ${Object.keys(CONDITIONS).join(', ')}`);
    }
    const started = ctx.realNow(); // real time: an episode's virtual clock may stand still meanwhile
    let last = null;
    let stillFor = 0;
    let previous;
    for (;;) {
      last = condition.check(args.args || {});
      if (last.done) {
        const same = previous !== undefined && JSON.stringify(last.value) === JSON.stringify(previous);
        stillFor = same ? stillFor + 1 : 0;
        if (!condition.still || stillFor >= STILL_POLLS) return {ok: true, value: last.value, waitedMs: ctx.realNow() - started};
      } else {
        stillFor = 0;
      }
      previous = last.value;
      if (ctx.realNow() - started > timeoutMs) return {ok: false, value: last.value, waitedMs: ctx.realNow() - started};
      await ctx.realSleep(POLL_MS);
    }
  }

  return {api: {geometryWait: (args) => wait(args)}};
}});
