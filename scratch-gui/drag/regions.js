/*
 * A drag task's exact feasible regions, in page pixels of the current view, from the editor's own
 * geometry rather than from trial drags:
 *
 * - start (`dragStartRegion`): every pixel where a press grabs the source. The browser's own hit
 *   test (`elementFromPoint`) says what is under the pixel; the press drags the nearest enclosing
 *   block that is not a shadow (Blockly hands a shadow's press to its parent), and only that block.
 * - end (`dragEndRegion`): every release position that, for a press at a given start and a straight
 *   path of `steps` moves, leaves Blockly's connection candidate on the expected connection
 *   (`geometry/drag-plan`'s replay of its choice, previews included), with the release outside every
 *   delete area (the palette), where Blockly deletes the block instead. A palette source is stood in
 *   for by a copy drawn over the palette block (where Blockly's new block appears), made and removed
 *   with events off so the VM never sees it; its connections start the drag at its origin, as the
 *   new block's do (Blockly starts dragging it before drawing it).
 *
 * Regions are run-length rows [y, xFirst, xLast]. Read-only for the project.
 */
scratchworldModule({name: 'drag/regions', requires: ['rects', 'blockly', 'geometry/views', 'geometry/drag-plan'], create(ctx, rects, blockly, views, plan) {
  'use strict';

  const fail = (message) => new ctx.BridgeFailure('bad_request', message);
  const notFound = (message) => new ctx.BridgeFailure('not_found', message);

  /* ---------- the source ---------- */

  function variableName(block) {
    const field = block.getField('VARIABLE');
    return field ? field.getText() : null;
  }

  // The source block as drawn: a workspace block by id, or the palette's block of an opcode.
  function sourceBlock(source) {
    if (!source || typeof source !== 'object') throw fail('source must be {kind, block_id | opcode}');
    if (source.kind === 'canvas') {
      const block = blockly.workspace().getBlockById(source.block_id);
      if (!block) throw notFound(`no block ${JSON.stringify(source.block_id)} on the workspace`);
      return {block: block, workspace: blockly.workspace(), flyout: false};
    }
    if (source.kind !== 'flyout') throw fail('source.kind must be canvas or flyout');
    const flyoutWs = blockly.flyout().getWorkspace();
    const block = flyoutWs.getTopBlocks(false).find((b) => b.type === source.opcode &&
      (!source.variable_name || variableName(b) === source.variable_name));
    if (!block) throw notFound(`the palette shows no ${source.opcode} block`);
    return {block: block, workspace: flyoutWs, flyout: true};
  }

  // The block a press at (x, y) would drag, or null.
  function grabbedAt(workspace, x, y) {
    const hit = document.elementFromPoint(x, y);
    let element = hit ? hit.closest('[data-id]') : null;
    while (element) {
      const block = workspace.getBlockById(element.getAttribute('data-id'));
      if (block && !block.isShadow()) return block;
      element = element.parentElement ? element.parentElement.closest('[data-id]') : null;
    }
    return null;
  }

  /* ---------- regions as run-length rows ---------- */

  function scan(box, inside) {
    const rows = [];
    const view = rects.viewport();
    const x0 = Math.max(0, Math.floor(box.x));
    const x1 = Math.min(view.width - 1, Math.ceil(rects.right(box)));
    const y0 = Math.max(0, Math.floor(box.y));
    const y1 = Math.min(view.height - 1, Math.ceil(rects.bottom(box)));
    for (let y = y0; y <= y1; y++) {
      let run = null;
      for (let x = x0; x <= x1; x++) {
        if (inside(x, y)) {
          if (run) run[2] = x;
          else run = [y, x, x];
        } else if (run) {
          rows.push(run);
          run = null;
        }
      }
      if (run) rows.push(run);
    }
    return rows;
  }

  function startRegion(args) {
    const found = sourceBlock(args.source);
    const box = rects.rectOf(found.block.getSvgRoot());
    const rows = scan(box, (x, y) => grabbedAt(found.workspace, x, y) === found.block);
    return {rows: rows, box: box};
  }

  /* ---------- the end region ---------- */

  const CONNECTION_NAMES = {next: 'next', substack_1: 'input:SUBSTACK', substack_2: 'input:SUBSTACK2'};

  // The pair of connections the expected connection joins: one of the moving block's, one of the reference's.
  function wantedPair(moving, reference, connection) {
    const kind = connection && connection.kind;
    let local;
    let neighbour;
    if (kind === 'parent') {
      local = moving.lastConnectionInStack(true);
      neighbour = reference.previousConnection;
    } else if (kind === 'input') {
      local = moving.outputConnection;
      neighbour = plan.connectionNamed(reference, `input:${connection.input_name}`);
    } else if (CONNECTION_NAMES[kind]) {
      local = moving.previousConnection;
      neighbour = plan.connectionNamed(reference, CONNECTION_NAMES[kind]);
    } else {
      throw fail(`unknown connection kind ${JSON.stringify(kind)}`);
    }
    if (!local) throw notFound(`the dragged ${moving.type} has no connection for ${kind}`);
    if (!neighbour) throw notFound(`${reference.type} has no connection for ${kind}`);
    return {local: local, neighbour: neighbour};
  }

  // A stand-in for the palette block, made and placed over it as the palette makes the block a drag
  // takes out of it (its own positionNewBlock, while the workspace does not resize: a resize would
  // scroll it, and the block would land a fraction of a pixel away from where Blockly puts it).
  function standIn(flyoutBlock) {
    const SB = blockly.scratchBlocks();
    const ws = blockly.workspace();
    const flyout = blockly.flyout();
    const block = SB.serialization.blocks.append(flyout.serializeBlock(flyoutBlock), ws, {recordUndo: false});
    flyout.positionNewBlock(flyoutBlock, block);
    SB.renderManagement.triggerQueuedRenders(ws);
    return block;
  }

  // Whether a release at (x, y) is over a delete area (the palette): the block is deleted there.
  function deletes(ws, block, x, y) {
    const target = ws.getDragTarget({clientX: x, clientY: y});
    if (!target) return false;
    const components = ws.getComponentManager();
    return components.hasCapability(target.id, blockly.scratchBlocks().ComponentManager.Capability.DELETE_AREA) &&
      target.wouldDelete(block);
  }

  // Runs `use(drag)` with the drag of the task's source from `args.start` prepared: the moving block
  // (a stand-in for a palette source, removed afterwards), the wanted pair, and `candidateAt(x, y)`,
  // the candidate a straight `steps`-move drag released at (x, y) ends on (null: none, or deleted).
  // All of it runs as if the drag were in progress, as a real one's choices are made.
  function withDrag(args, use) {
    return blockly.asIfDragging(() => simulateDrag(args, use));
  }

  function simulateDrag(args, use) {
    const ws = blockly.workspace();
    const SB = blockly.scratchBlocks();
    const start = args.start;
    if (!start || typeof start.x !== 'number' || typeof start.y !== 'number') throw fail('start must be {x, y}');
    const steps = Math.max(1, Math.min(100, Number(args.steps) || 15));
    const found = sourceBlock(args.source);
    const reference = ws.getBlockById(args.reference);
    if (!reference) throw notFound(`no block ${JSON.stringify(args.reference)} on the workspace`);
    const radius = found.flyout ? SB.config.flyoutDragRadius : SB.config.dragRadius;
    let moving = found.block;
    // A block dragged out of a script leaves it as the drag starts (with the blocks below it), and the
    // script closes up behind it: the drag is matched against the script as it is then.
    const own = found.flyout ? null : moving.previousConnection || moving.outputConnection;
    const parent = own && own.targetConnection;
    SB.Events.disable();
    try {
      if (found.flyout) moving = standIn(found.block);
      if (parent) {
        moving.unplug(false);
        SB.renderManagement.triggerQueuedRenders(ws);
      }
      const pair = wantedPair(moving, reference, args.connection);
      const neighbours = plan.neighbourConnections(moving);
      const previews = new Map();
      // A block Blockly creates from the palette starts its drag before it is first drawn: all its
      // connections are still at its origin then, and a drag matches them from there.
      let localAt = null;
      if (found.flyout) {
        const origin = moving.getRelativeToSurfaceXY();
        localAt = new Map(plan.localConnections(moving).map((c) => [c, {x: origin.x, y: origin.y}]));
      }
      const from = (local) => (localAt && localAt.get(local)) || local;
      const scale = ws.scale;
      ws.recordDragTargets();
      const candidateAt = (x, y, visit) => {
        if (Math.hypot(x - start.x, y - start.y) <= radius) return null; // a click, not a drag
        const deltas = [];
        for (let i = 1; i <= steps; i++) {
          const px = start.x + (x - start.x) * i / steps;
          const py = start.y + (y - start.y) * i / steps;
          // Blockly starts the drag on the first move past the drag radius.
          if (deltas.length === 0 && Math.hypot(px - start.x, py - start.y) <= radius) continue;
          deltas.push({x: (px - start.x) / scale, y: (py - start.y) / scale});
        }
        const last = plan.replayCandidates(moving, deltas, {visit: visit, neighbours: neighbours, previews: previews, localAt: localAt});
        return last && !deletes(ws, moving, x, y) ? last : null;
      };
      return use({moving: moving, pair: pair, scale: scale, from: from, candidateAt: candidateAt});
    } finally {
      if (moving !== found.block) moving.dispose(false);
      if (parent) {
        parent.connect(own);
        SB.renderManagement.triggerQueuedRenders(ws);
      }
      SB.Events.enable();
    }
  }

  function endRegion(args) {
    const config = blockly.scratchBlocks().config;
    return withDrag(args, (drag) => {
      const {pair, scale, from, candidateAt} = drag;
      // The release that puts `local` on `neighbour` exactly, and every release that can still end on
      // it: a current candidate outlives its snap radius while another connection is in reach and not
      // `currentConnectionPreference` closer than it (Blockly's own rule), so that far and no farther.
      const local = from(pair.local);
      const aim = {x: args.start.x + (pair.neighbour.x - local.x) * scale, y: args.start.y + (pair.neighbour.y - local.y) * scale};
      const reach = (Math.max(config.snapRadius, config.connectingSnapRadius) + config.currentConnectionPreference) * scale + 2;
      const rows = scan({x: aim.x - reach, y: aim.y - reach, width: 2 * reach, height: 2 * reach}, (x, y) => {
        const last = candidateAt(x, y);
        return !!last && last.local === pair.local && last.neighbour === pair.neighbour;
      });
      return {rows: rows, aim: aim};
    });
  }

  // What a release at `end` would connect, in words, and the candidate after each move (for explaining a miss).
  function candidateAt(args) {
    const end = args.end;
    if (!end || typeof end.x !== 'number' || typeof end.y !== 'number') throw fail('end must be {x, y}');
    const describe = (pair) => (pair ? `${plan.describeConnection(pair.local)} to ${plan.describeConnection(pair.neighbour)}` : null);
    return withDrag(args, (drag) => {
      const steps = [];
      const last = drag.candidateAt(end.x, end.y, (current) => { steps.push(describe(current)); });
      const wanted = !!last && last.local === drag.pair.local && last.neighbour === drag.pair.neighbour;
      return {candidate: describe(last), wanted: wanted, steps: steps};
    });
  }

  return {
    sourceBlock: sourceBlock,
    api: {dragStartRegion: (args) => startRegion(args), dragEndRegion: (args) => endRegion(args), dragCandidateAt: (args) => candidateAt(args)},
  };
}});
