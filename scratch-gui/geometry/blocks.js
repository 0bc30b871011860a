/*
 * Blocks as drawn: where a block, its connections and its fields are, a point on its own body
 * that a press grabs, its fields' values and dropdown choices, and the palette's blocks and
 * buttons. Read-only.
 */
scratchworldModule({name: 'geometry/blocks', requires: ['rects', 'blockly', 'geometry/views'], create(ctx, rects, blockly, views) {
  'use strict';

  const fail = (message) => new ctx.BridgeFailure('bad_request', message);

  // Connection types of Blockly: input value, output, next statement, previous statement.
  const INPUT_VALUE = 1;
  const NEXT_STATEMENT = 3;

  /* ---------- blocks ---------- */

  function liveBlock(id) {
    if (typeof id !== 'string' || !id) throw fail('id must be a non-empty string');
    const block = blockly.workspace().getBlockById(id);
    if (!block) throw new ctx.BridgeFailure('not_found', `no block ${JSON.stringify(id)} in the visible workspace`);
    return block;
  }

  function connectionAt(ws, connection) {
    if (!connection) return null;
    const point = views.toPage(ws, connection.x, connection.y);
    point.connected = !!connection.targetConnection;
    return point;
  }

  // A point on the block's own body (not a child block, not an editable field) that a press
  // hits, scanning from the left edge; null when no such point is visible inside `area`.
  function grabPoint(ws, block, area) {
    const r = rects.rectOf(block.getSvgRoot());
    const canvas = ws.getCanvas();
    for (let x = Math.ceil(r.x + 2); x < rects.right(r) - 1; x += 3) {
      for (let y = Math.ceil(r.y + 2); y < rects.bottom(r) - 1; y += 3) {
        if (!rects.inside(area, x, y)) continue;
        const hit = document.elementFromPoint(x, y);
        if (!hit || !canvas.contains(hit)) continue;
        const owner = hit.closest('[data-id]');
        if (!owner || owner.getAttribute('data-id') !== block.id) continue;
        if (hit.closest('.blocklyEditableField, .blocklyEditableText')) continue;
        return {x: x, y: y};
      }
    }
    return null;
  }

  function shapeOf(block) {
    return {
      hat: !block.previousConnection && !block.outputConnection,
      reporter: !!block.outputConnection,
      previous: !!block.previousConnection,
      next: !!block.nextConnection
    };
  }

  // Where the block hangs: {parent, input} (input null: the parent's next), or null when top-level.
  function attachmentOf(block) {
    const parent = block.getParent();
    if (!parent) return null;
    const input = parent.getInputWithBlock(block);
    return {parent: parent.id, input: input ? input.name : null};
  }

  function blockInfo(args) {
    const ws = blockly.workspace();
    const block = liveBlock(args.id);
    const inputs = {};
    for (const input of block.inputList) {
      if (!input.name || !input.connection) continue;
      const point = connectionAt(ws, input.connection);
      point.kind = input.connection.type === NEXT_STATEMENT ? 'statement' : input.connection.type === INPUT_VALUE ? 'value' : 'other';
      const child = input.connection.targetBlock();
      point.block = child ? child.id : null;
      point.shadow = !!(child && child.isShadow());
      inputs[input.name] = point;
    }
    let last = block;
    while (last.getNextBlock()) last = last.getNextBlock();
    const next = block.getNextBlock();
    return {
      id: block.id,
      opcode: block.type,
      rect: rects.rectOf(block.getSvgRoot()),
      grab: grabPoint(ws, block, views.safeArea()),
      shape: shapeOf(block),
      attachment: attachmentOf(block),
      root: block.getRootBlock().id,
      nextBlock: next ? next.id : null,
      previous: connectionAt(ws, block.previousConnection),
      next: connectionAt(ws, block.nextConnection),
      output: connectionAt(ws, block.outputConnection),
      lastNext: connectionAt(ws, last.nextConnection),
      inputs: inputs
    };
  }

  /* ---------- fields ---------- */

  function optionText(option) {
    const label = option[0];
    if (typeof label === 'string') return label;
    return label && typeof label === 'object' && label.alt ? String(label.alt) : String(option[1]);
  }

  function editableField(block) {
    for (const input of block.inputList) {
      for (const field of input.fieldRow) if (field.name && field.EDITABLE) return field;
    }
    return null;
  }

  // The field a value goes into: a field of the block, or the field of the shadow in an input.
  function fieldOf(block, name) {
    const own = block.getField(name);
    if (own) return own;
    const input = block.getInput(name);
    if (!input || !input.connection) throw new ctx.BridgeFailure('not_found', `${block.type} has no field or input ${JSON.stringify(name)}`);
    const child = input.connection.targetBlock();
    if (!child) throw new ctx.BridgeFailure('not_found', `input ${name} of ${block.type} is empty: there is no field to click`);
    if (!child.isShadow()) throw new ctx.BridgeFailure('not_found', `input ${name} of ${block.type} holds a block (${child.type}), not a value`);
    const field = editableField(child);
    if (!field) throw new ctx.BridgeFailure('not_found', `the ${child.type} in input ${name} of ${block.type} has no editable field`);
    return field;
  }

  function fieldInfo(args) {
    const block = liveBlock(args.id);
    if (typeof args.name !== 'string') throw fail('name must be a string');
    const field = fieldOf(block, args.name);
    const ColourSlider = blockly.scratchBlocks().FieldColourSlider;
    const colour = !!ColourSlider && field instanceof ColourSlider;
    const dropdown = !colour && typeof field.getOptions === 'function';
    let options = null;
    if (dropdown) {
      try {
        options = field.getOptions(false).map((option) => ({text: optionText(option), value: String(option[1])}));
      } catch (e) {
        options = [];
      }
    }
    // An empty text draws no box: a click on its shadow block (the field's only one) opens its editor.
    let root = field.getSvgRoot();
    const drawn = root ? rects.rectOf(root) : null;
    const source = field.getSourceBlock();
    if (drawn && (drawn.width < 2 || drawn.height < 2) && source && source.isShadow()) root = source.getSvgRoot();
    return {
      kind: colour ? 'colour' : dropdown ? 'dropdown' : 'text',
      name: field.name,
      value: field.getValue() === null ? null : String(field.getValue()),
      text: field.getText(),
      rect: root ? rects.rectOf(root) : null,
      options: options
    };
  }

  // {fieldName: value} of a VM block and of the shadows in its inputs, as the VM stores them.
  function blockFields(args) {
    const target = ctx.requireVm().editingTarget;
    const block = target && target.blocks.getBlock(args.id);
    if (!block) throw new ctx.BridgeFailure('not_found', `no block ${JSON.stringify(args.id)} in the editing target`);
    const fields = {};
    for (const [name, field] of Object.entries(block.fields)) fields[name] = String(field.value);
    const inputs = {};
    for (const [name, input] of Object.entries(block.inputs)) {
      const child = input.block && target.blocks.getBlock(input.block);
      if (child && child.shadow) {
        const first = Object.values(child.fields)[0];
        if (first) inputs[name] = String(first.value);
      }
    }
    return {opcode: block.opcode, fields: fields, inputs: inputs};
  }

  /* ---------- palette ---------- */

  function flyoutState() {
    const theFlyout = blockly.flyout();
    return {scrollY: theFlyout.getWorkspace().scrollY, animating: theFlyout.scrollTarget !== undefined};
  }

  function flyoutBlock(args) {
    if (typeof args.opcode !== 'string') throw fail('opcode must be a string');
    const theFlyout = blockly.flyout();
    const fws = theFlyout.getWorkspace();
    const view = views.flyoutView();
    const candidates = fws.getTopBlocks(false).filter((b) => b.type === args.opcode);
    const wanted = args.variableName;
    const block = candidates.find((b) => {
      if (typeof wanted !== 'string') return true;
      const field = b.getField('VARIABLE') || b.getField('LIST');
      return !!field && field.getText() === wanted;
    });
    if (!block) return {found: false, count: candidates.length, flyout: view};
    const rect = rects.rectOf(block.getSvgRoot());
    return {
      found: true,
      id: block.id,
      rect: rect,
      visible: rect.y >= view.y && rects.bottom(rect) <= rects.bottom(view) - 2,
      grab: grabPoint(fws, block, view),
      flyout: view,
      flyoutScale: fws.scale,
      workspaceScale: blockly.workspace().scale
    };
  }

  function flyoutButton(args) {
    const view = views.flyoutView();
    for (const element of document.querySelectorAll('.blocklyFlyout .blocklyFlyoutButton')) {
      if (element.textContent.trim() !== args.text) continue;
      const rect = rects.rectOf(element);
      return {found: true, rect: rect, visible: rect.y >= view.y && rects.bottom(rect) <= rects.bottom(view) - 2, flyout: view};
    }
    return {found: false, flyout: view};
  }

  return {
    liveBlock: liveBlock, grabPoint: grabPoint, blockFields: blockFields, flyoutState: flyoutState, optionText: optionText,
    api: {
      geometryBlock: (args) => blockInfo(args),
      geometryField: (args) => fieldInfo(args),
      geometryBlockFields: (args) => blockFields(args),
      geometryFlyoutBlock: (args) => flyoutBlock(args),
      geometryFlyoutButton: (args) => flyoutButton(args),
    },
  };
}});
