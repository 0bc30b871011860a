/*
 * Planning a drag that connects two blocks: Blockly's own choice of connection replayed along a
 * straight mouse path (its snap radii, its preference for the current candidate), so a path is
 * known to snap only to the wanted connection before any mouse moves; and free spots of the
 * workspace where a block can wait without snapping to anything. Read-only.
 */
scratchworldModule({name: 'geometry/drag-plan', requires: ['rects', 'blockly', 'geometry/views', 'geometry/blocks'], create(ctx, rects, blockly, views, blocks) {
  'use strict';

  const fail = (message) => new ctx.BridgeFailure('bad_request', message);

  const GRID = 8;

  /* ---------- empty space ---------- */

  // Top-left corners (page pixels) of free width x height boxes inside the usable workspace,
  // farther than any snap radius from every block (but those in `ignore`), nearest to `near` first.
  function freeSpots(width, height, ignore, near, limit) {
    const ws = blockly.workspace();
    const area = views.safeArea();
    const config = blockly.scratchBlocks().config;
    const margin = Math.max(config.snapRadius, config.connectingSnapRadius) * ws.scale + GRID;
    const obstacles = ws.getTopBlocks(false).filter((b) => !ignore.includes(b.id)).map((b) => rects.grow(rects.rectOf(b.getSvgRoot()), margin));
    for (const r of views.overlays()) obstacles.push(rects.grow(r, GRID));
    const from = near || {x: area.x, y: area.y};
    const spots = [];
    for (let y = area.y; y + height <= rects.bottom(area); y += GRID) {
      for (let x = area.x; x + width <= rects.right(area); x += GRID) {
        const box = {x: x, y: y, width: width, height: height};
        if (!obstacles.some((o) => rects.overlaps(o, box))) spots.push({x: x, y: y, d: Math.hypot(x - from.x, y - from.y)});
      }
    }
    spots.sort((a, b) => a.d - b.d);
    return spots.slice(0, limit).map((s) => ({x: s.x, y: s.y}));
  }

  function freeSpot(args) {
    const width = Number(args.width);
    const height = Number(args.height);
    if (!(width > 0) || !(height > 0)) throw fail('width and height must be positive');
    const near = args.near && typeof args.near.x === 'number' ? args.near : null;
    const spots = freeSpots(width, height, args.ignore || [], near, 1);
    return {spot: spots.length ? spots[0] : null, area: views.safeArea()};
  }

  /* ---------- planning a connecting drag ---------- */

  const OPPOSITE = {1: 2, 2: 1, 3: 4, 4: 3};

  // A connection of a block by name: previous, next, output, lastNext (the end of its stack),
  // parent (the connection the block hangs from) or input:NAME.
  function connectionNamed(block, spec) {
    if (spec === 'previous') return block.previousConnection;
    if (spec === 'next') return block.nextConnection;
    if (spec === 'output') return block.outputConnection;
    if (spec === 'lastNext') return block.lastConnectionInStack(true);
    if (spec === 'parent') {
      const own = block.previousConnection || block.outputConnection;
      return own ? own.targetConnection : null;
    }
    if (typeof spec === 'string' && spec.startsWith('input:')) {
      const input = block.getInput(spec.slice(6));
      return input ? input.connection : null;
    }
    return null;
  }

  // The connections a drag of `moving` offers (Blockly's own choice: the block's connections and
  // the last next connection of its stack).
  function localConnections(moving) {
    const found = moving.getConnections_(false);
    const last = moving.lastConnectionInStack(true);
    if (last && last !== moving.nextConnection) found.push(last);
    return found;
  }

  function describeConnection(connection) {
    const block = connection.getSourceBlock();
    const names = {1: 'input', 2: 'output', 3: 'next', 4: 'previous'};
    let what = names[connection.type];
    for (const input of block.inputList) if (input.connection === connection) what = `input ${input.name}`;
    return `${what} of ${block.type} ${block.id}`;
  }

  // Replays Blockly's choice of connection along the mouse path (the drag strategy's closest
  // candidate, its radii and its preference for the current candidate), without insertion-marker
  // previews: a path is clean when no connection but the wanted one is ever the candidate, so
  // no preview can move the wanted connection away, and the drop ends on it.
  function simulatePath(moving, deltas, wanted) {
    const ws = blockly.workspace();
    const config = blockly.scratchBlocks().config;
    const checker = ws.connectionChecker;
    const own = new Set(moving.getDescendants(false));
    const locals = localConnections(moving);
    const candidates = [];
    for (const block of ws.getAllBlocks(false)) {
      if (own.has(block) || block.isInsertionMarker()) continue;
      for (const connection of block.getConnections_(false)) candidates.push(connection);
    }
    const distance = (local, delta, other) => Math.hypot(local.x + delta.x - other.x, local.y + delta.y - other.y);
    let current = null;
    for (let i = 0; i < deltas.length; i++) {
      const delta = deltas[i];
      let best = null;
      let radius = current ? config.connectingSnapRadius : config.snapRadius;
      for (const local of locals) {
        for (const other of candidates) {
          if (other.type !== OPPOSITE[local.type]) continue;
          const d = distance(local, delta, other);
          if (d > radius || !checker.canConnect(local, other, true, Infinity)) continue;
          best = {local: local, neighbour: other, distance: d};
          radius = d;
        }
      }
      if (!best) {
        current = null;
        continue;
      }
      if (!current || !(best.distance > distance(current.local, delta, current.neighbour) - config.currentConnectionPreference)) current = best;
      if (current.local !== wanted.local || current.neighbour !== wanted.neighbour) {
        return {clean: false, step: i + 1, candidate: describeConnection(current.neighbour)};
      }
    }
    if (!current) return {clean: false, step: deltas.length, candidate: null};
    return {clean: true};
  }

  function mousePath(start, end, steps) {
    const points = [];
    for (let i = 1; i <= steps; i++) points.push({x: start.x + (end.x - start.x) * i / steps, y: start.y + (end.y - start.y) * i / steps});
    return points;
  }

  // How to drag `moving` so that its connection `local` meets connection `remote` of `target`:
  // the press and release points, whether the straight path snaps only to the wanted connection,
  // and if not, a free spot from which it would (move the block there first).
  function planDrag(args) {
    const ws = blockly.workspace();
    const moving = blocks.liveBlock(args.moving);
    const target = blocks.liveBlock(args.target);
    const local = connectionNamed(moving, args.local);
    const remote = connectionNamed(target, args.remote);
    if (!local) throw new ctx.BridgeFailure('not_found', `${moving.type} has no ${args.local} connection`);
    if (!remote) throw new ctx.BridgeFailure('not_found', `${target.type} has no ${args.remote} connection`);
    const steps = Math.max(1, Number(args.steps) || 10);
    const area = views.safeArea();
    const scale = ws.scale;
    const rect = rects.rectOf(moving.getSvgRoot());
    const localPage = views.toPage(ws, local.x, local.y);
    const remotePage = views.toPage(ws, remote.x, remote.y);
    const grab = blocks.grabPoint(ws, moving, area);
    const reference = grab || rects.centre(rect);
    const end = {x: reference.x + remotePage.x - localPage.x, y: reference.y + remotePage.y - localPage.y};
    const plan = {grab: grab, end: end, rect: rect, reference: reference, endVisible: rects.inside(area, end.x, end.y)};
    if (!grab || !plan.endVisible) return Object.assign(plan, {clean: false, reason: 'out of view'});
    const wanted = {local: local, neighbour: remote};
    const toDeltas = (start) => mousePath(start, end, steps).map((p) => ({x: (p.x - grab.x) / scale, y: (p.y - grab.y) / scale}));
    const direct = simulatePath(moving, toDeltas(grab), wanted);
    if (direct.clean) return Object.assign(plan, {clean: true});
    plan.clean = false;
    plan.reason = direct.candidate ? `the path meets ${direct.candidate} first (mouse step ${direct.step})` : 'the drop does not reach the connection';
    // Staging spots: free places for the block, nearest to the destination first.
    const spots = freeSpots(rect.width, rect.height, moving.getParent() ? [] : [moving.id], remotePage, 400);
    for (const spot of spots) {
      const start = {x: spot.x + grab.x - rect.x, y: spot.y + grab.y - rect.y};
      if (Math.hypot(start.x - end.x, start.y - end.y) < 4) continue;
      if (simulatePath(moving, toDeltas(start), wanted).clean) {
        plan.staging = {spot: spot, end: start};
        break;
      }
    }
    return plan;
  }

  return {
    api: {geometryFreeSpot: (args) => freeSpot(args), geometryPlanDrag: (args) => planDrag(args)},
  };
}});
