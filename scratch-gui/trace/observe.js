/*
 * What a user could see of the VM at one moment (the observable trace, trace/record.js): per target,
 * flat JSON fields that two runs of a project can be compared by. A sprite: its bubble, position,
 * direction, size, costume, visibility, graphic effects and rotation style; every target: its
 * variables and lists, keyed `var:<variable id>` as [name, value, monitor shown]; the stage: its
 * backdrop and the sprites' layer order. Only reads: taking a snapshot changes nothing in the VM.
 */
scratchworldModule({name: 'trace/observe', create() {
  'use strict';

  const EFFECTS = ['color', 'fisheye', 'whirl', 'pixelate', 'mosaic', 'brightness', 'ghost'];

  // Positions and sizes to a millionth: far below a stage pixel, above the float noise of two ways
  // of computing the same place (a user sees 0.1 + 0.2 where the sprite would be at 0.3).
  const round = (value) => (typeof value === 'number' && Number.isFinite(value) ? Math.round(value * 1e6) / 1e6 : value);

  /** The graphic effects that are not zero (a cleared sprite has `{}`). */
  function effectsOf(target) {
    const shown = {};
    for (const name of EFFECTS) if (target.effects && target.effects[name]) shown[name] = round(target.effects[name]);
    return shown;
  }

  /** The say or think bubble as the looks blocks keep it (text formatted as shown, cleared on stop): [kind, text] or null. */
  function bubbleOf(target) {
    const state = target.getCustomState('Scratch.looks');
    return state && state.text ? [state.type, String(state.text)] : null;
  }

  function costumeOf(target) {
    const costume = target.getCostumes()[target.currentCostume];
    return costume ? costume.name : null;
  }

  /** How a sprite looks, as the stage shows it (also what a pen stamp prints). */
  function appearance(target) {
    return {
      x: round(target.x), y: round(target.y), direction: round(target.direction), size: round(target.size),
      costume: costumeOf(target), visible: !!target.visible, effects: effectsOf(target), rotation: target.rotationStyle,
    };
  }

  // Values as Scratch shows them (a monitor or a bubble shows 10 and "10" alike).
  const shown = (value) => (Array.isArray(value) ? value.map((item) => String(item)) : String(value));

  // Variable monitors are keyed by the variable's id; a clone's copies have no monitor of their own.
  function addVariables(target, monitors, fields) {
    for (const id of Object.keys(target.variables)) {
      const variable = target.variables[id];
      if (variable.type === 'broadcast_msg') continue;
      const monitor = target.isOriginal && monitors ? monitors.get(id) : null;
      fields[`var:${id}`] = [variable.name, shown(variable.value), !!(monitor && monitor.visible)];
    }
  }

  // Drawable id -> place in the renderer's draw list (back to front).
  function drawOrder(renderer) {
    const order = new Map();
    const list = renderer && renderer._drawList;
    if (Array.isArray(list)) list.forEach((id, index) => order.set(id, index));
    return order;
  }

  /**
   * Every target's fields, stage first, then the sprites and clones back to front: a Map from the key
   * `keyOf` gives a target to its fields.
   */
  function snapshot(vm, keyOf) {
    const runtime = vm.runtime;
    const monitors = runtime._monitorState;
    const order = drawOrder(runtime.renderer);
    const place = (target) => (order.has(target.drawableID) ? order.get(target.drawableID) : Infinity);
    const sprites = runtime.targets.filter((target) => !target.isStage);
    sprites.sort((a, b) => place(a) - place(b)); // stable: without a renderer, creation order
    const result = new Map();
    const stage = runtime.getTargetForStage();
    if (stage) {
      const fields = {costume: costumeOf(stage), effects: effectsOf(stage), layers: sprites.map(keyOf)};
      addVariables(stage, monitors, fields);
      result.set(keyOf(stage), fields);
    }
    for (const sprite of sprites) {
      const fields = appearance(sprite);
      fields.bubble = bubbleOf(sprite);
      addVariables(sprite, monitors, fields);
      result.set(keyOf(sprite), fields);
    }
    return result;
  }

  return {snapshot, appearance};
}});
