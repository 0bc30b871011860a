/*
 * What a screenshot of the workspace shows, block by block, for perception questions whose answers
 * come from the editor rather than from a reader: the visible workspace area, and for every
 * non-shadow block of the editing target its place in the scripts (parent, next, the input it sits
 * in), its own body's rectangle, how much of that body and of its label can be seen, and the values
 * its fields show. Read-only; Python derives questions and answers from this (`perceptionFacts`).
 *
 * "Seen" is decided by the browser's own hit test: a sample point counts for a block when the
 * topmost element there belongs to the block itself (its path, labels, or the shadows in its
 * inputs), inside the visible area. A point under one of the block's own children (a reporter in
 * its slot, the next block's tab) is left out of its count; a point under another script, the zoom
 * buttons, a scrollbar or outside the visible area counts as hidden. Each block gets at most
 * BODY_POINTS body points (3 px apart at the least), so a view costs a bounded number of hit tests.
 */
scratchworldModule({name: 'perception/facts', requires: ['rects', 'blockly', 'geometry/views', 'geometry/blocks'], create(ctx, rects, blockly, views, geometryBlocks) {
  'use strict';

  const MAX_BLOCKS = 1500;
  const BODY_POINTS = 160;
  const MIN_STEP = 3;
  const FIELD_POINTS = 24;
  const MAX_OPTIONS = 40;
  const MAX_TEXT = 200;
  // Bands at the top and bottom of a body (a share of its height) where a stack joins its neighbours.
  const BAND = 0.25;
  const SCROLLBAR = 12;
  // Dropdown entries that are commands, not values.
  const COMMANDS = new Set(['RENAME_VARIABLE_ID', 'DELETE_VARIABLE_ID', 'NEW_BROADCAST_MESSAGE_ID']);
  const NUMBER_SHADOWS = new Set(['math_number', 'math_positive_number', 'math_whole_number', 'math_integer', 'math_angle']);
  // Blockly's connection types: an input that takes a reporter, one that takes a stack.
  const INPUT_VALUE = 1;
  const NEXT_STATEMENT = 3;

  // The workspace area a screenshot shows: right of the palette, without the scrollbars.
  function visibleArea() {
    const view = views.workspaceView();
    return {x: view.x, y: view.y, width: Math.max(0, view.width - SCROLLBAR), height: Math.max(0, view.height - SCROLLBAR)};
  }

  const oneLine = (text) => String(text).replace(/\s+/g, ' ').trim().slice(0, MAX_TEXT);

  function grid(r, maxPoints, minStep) {
    if (r.width <= 0 || r.height <= 0) return [];
    const step = Math.max(minStep, Math.sqrt((r.width * r.height) / maxPoints));
    const columns = Math.max(1, Math.floor(r.width / step));
    const rows = Math.max(1, Math.floor(r.height / step));
    const points = [];
    for (let i = 0; i < columns; i++) {
      for (let j = 0; j < rows; j++) points.push({x: r.x + (i + 0.5) * (r.width / columns), y: r.y + (j + 0.5) * (r.height / rows)});
    }
    return points;
  }

  function hitTester(ws, area) {
    const canvas = ws.getCanvas();
    // The non-shadow block that owns the topmost element at a point (a shadow answers for its
    // parent), or null when no block of the workspace is there.
    return function owner(x, y) {
      if (!rects.inside(area, x, y)) return null;
      const hit = document.elementFromPoint(x, y);
      if (!hit || !canvas.contains(hit)) return null;
      let group = hit.closest('[data-id]');
      while (group) {
        const block = ws.getBlockById(group.getAttribute('data-id'));
        if (block && !block.isShadow()) return block;
        group = group.parentElement ? group.parentElement.closest('[data-id]') : null;
      }
      return null;
    };
  }

  const descends = (block, from) => {
    for (let b = block; b; b = b.getParent()) if (b === from) return true;
    return false;
  };

  // How much of the block's own body can be seen: overall, and in its top and bottom bands.
  function bodyVisibility(block, path, r, owner) {
    const counts = {all: [0, 0], top: [0, 0], bottom: [0, 0]};
    const matrix = path.getScreenCTM();
    if (!matrix) return counts;
    const inverse = matrix.inverse();
    for (const p of grid(r, BODY_POINTS, MIN_STEP)) {
      const local = new DOMPoint(p.x, p.y).matrixTransform(inverse);
      if (!path.isPointInFill(local)) continue;
      const who = owner(p.x, p.y);
      let seen;
      if (who === block) seen = 1;
      else if (who && who !== block && descends(who, block)) continue; // its own child lies on it
      else seen = 0;
      const add = (c) => { c[0] += seen; c[1] += 1; };
      add(counts.all);
      if (p.y < r.y + r.height * BAND) add(counts.top);
      if (p.y > r.y + r.height * (1 - BAND)) add(counts.bottom);
    }
    return counts;
  }

  const share = (c) => ({seen: c[0], points: c[1]});

  function seenIn(r, block, owner, maxPoints) {
    let seen = 0;
    const points = grid(r, maxPoints, 1);
    for (const p of points) if (owner(p.x, p.y) === block) seen++;
    return {seen: seen, points: points.length};
  }

  // The block's own words (not its values, not its icons: a flag or a loop arrow names nothing a reader
  // needs), how much of them can be seen, and the height of the shortest.
  function labelOf(block, owner) {
    const words = [];
    let seen = 0;
    let points = 0;
    let height = null;
    for (const input of block.inputList) {
      for (const field of input.fieldRow) {
        const root = field.getSvgRoot();
        if (field.EDITABLE || !root || !root.querySelector('text')) continue;
        const r = rects.rectOf(root);
        words.push(field.getText());
        const counted = seenIn(r, block, owner, FIELD_POINTS);
        seen += counted.seen;
        points += counted.points;
        if (r.height > 0) height = height === null ? r.height : Math.min(height, r.height);
      }
    }
    return {text: oneLine(words.join(' ')), seen: seen, points: points, height: height};
  }

  function fieldFacts(name, kind, field, block, owner) {
    const root = field.getSvgRoot();
    const r = root ? rects.rectOf(root) : {x: 0, y: 0, width: 0, height: 0};
    const text = field.getText();
    const shownElement = root ? root.querySelector('text') : null;
    const facts = {
      name: name,
      kind: kind,
      text: text.slice(0, MAX_TEXT),
      shown: shownElement ? shownElement.textContent.replace(/\u00a0/g, ' ').slice(0, MAX_TEXT) : null,
      rect: r,
      visibility: seenIn(r, block, owner, FIELD_POINTS),
      options: null
    };
    if (kind === 'dropdown') {
      let options = [];
      try {
        options = field.getOptions(false).filter((o) => !COMMANDS.has(String(o[1]))).map(geometryBlocks.optionText);
      } catch (e) {
        options = [];
      }
      facts.options = options.slice(0, MAX_OPTIONS).map((o) => o.slice(0, MAX_TEXT));
    }
    return facts;
  }

  // Its own dropdowns, and the values of the shadows in its inputs, in reading order.
  function fieldsOf(block, owner) {
    const found = [];
    for (const input of block.inputList) {
      for (const field of input.fieldRow) {
        if (field.EDITABLE && field.name && typeof field.getOptions === 'function') found.push(fieldFacts(field.name, 'dropdown', field, block, owner));
      }
      const child = input.connection && input.connection.targetBlock();
      if (!child || !child.isShadow()) continue;
      const field = child.inputList.flatMap((i) => i.fieldRow).find((f) => f.EDITABLE && f.name);
      if (!field) continue;
      const kind = typeof field.getOptions === 'function' ? 'dropdown' : NUMBER_SHADOWS.has(child.type) ? 'number' : child.type === 'text' ? 'text' : 'other';
      found.push(fieldFacts(input.name, kind, field, block, owner));
    }
    return found;
  }

  function inputsOf(block) {
    const found = [];
    for (const input of block.inputList) {
      if (!input.name || !input.connection) continue;
      const type = input.connection.type;
      const check = input.connection.getCheck ? input.connection.getCheck() : null;
      const child = input.connection.targetBlock();
      found.push({
        name: input.name,
        kind: type === NEXT_STATEMENT ? 'statement' : type === INPUT_VALUE ? (check && check.includes('Boolean') ? 'boolean' : 'value') : 'other',
        block: child && !child.isShadow() ? child.id : null
      });
    }
    return found;
  }

  function blockFacts(block, area, owner) {
    const path = block.pathObject && block.pathObject.svgPath;
    const r = path ? rects.rectOf(path) : rects.rectOf(block.getSvgRoot());
    const parent = block.getParent();
    const input = parent ? parent.getInputWithBlock(block) : null;
    const next = block.getNextBlock();
    const xy = block.getRelativeToSurfaceXY();
    const inView = !!rects.intersection(r, area);
    const body = inView && path ? bodyVisibility(block, path, r, owner) : {all: [0, 0], top: [0, 0], bottom: [0, 0]};
    const label = inView ? labelOf(block, owner) : {text: '', seen: 0, points: 0, height: null};
    return {
      id: block.id,
      opcode: block.type,
      parent: parent ? parent.id : null,
      input: input ? input.name : null,
      next: next ? next.id : null,
      xy: {x: xy.x, y: xy.y},
      rect: r,
      reporter: !!block.outputConnection,
      body: share(body.all),
      top: share(body.top),
      bottom: share(body.bottom),
      label: {text: label.text, seen: label.seen, points: label.points, height: label.height},
      fields: inView ? fieldsOf(block, owner) : [],
      inputs: inputsOf(block)
    };
  }

  function facts() {
    const ws = blockly.workspace();
    const vm = ctx.requireVm();
    const area = visibleArea();
    const owner = hitTester(ws, area);
    const all = ws.getAllBlocks(false).filter((b) => !b.isShadow() && !(b.isInsertionMarker && b.isInsertionMarker()));
    const started = performance.now();
    const blocks = all.slice(0, MAX_BLOCKS).map((b) => blockFacts(b, area, owner));
    return {
      target: vm.editingTarget ? vm.editingTarget.getName() : null,
      stage: !!(vm.editingTarget && vm.editingTarget.isStage),
      area: area,
      // The palette is translucent: blocks under it stay faintly visible (Python counts them as in view).
      palette: views.flyoutView(),
      scale: ws.scale,
      // Where the workspace SVG starts on the page: a view's scroll is workspace units at this corner.
      origin: (({left, top}) => ({x: left, y: top}))(ws.getParentSvg().getBoundingClientRect()),
      blocks: blocks,
      truncated: all.length > MAX_BLOCKS,
      ms: Math.round(performance.now() - started)
    };
  }

  return {api: {perceptionFacts: () => facts()}};
}});
