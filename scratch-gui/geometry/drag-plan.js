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

  // Top-left corners (page pixels) of free width x height boxes inside the usable workspace, on a
  // `grid`-pixel grid (default GRID), farther than any snap radius from every block (but those in
  // `ignore`), nearest to `near` first.
  function freeSpots(width, height, ignore, near, limit, grid) {
    const stride = grid || GRID;
    const ws = blockly.workspace();
    const area = views.safeArea();
    const config = blockly.scratchBlocks().config;
    const margin = Math.max(config.snapRadius, config.connectingSnapRadius) * ws.scale + GRID;
    const obstacles = ws.getTopBlocks(false).filter((b) => !ignore.includes(b.id)).map((b) => rects.grow(rects.rectOf(b.getSvgRoot()), margin));
    for (const r of views.overlays()) obstacles.push(rects.grow(r, GRID));
    const from = near || {x: area.x, y: area.y};
    const spots = [];
    for (let y = area.y; y + height <= rects.bottom(area); y += stride) {
      for (let x = area.x; x + width <= rects.right(area); x += stride) {
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
  const OUTPUT_VALUE = 2;
  const PREVIOUS_STATEMENT = 4;

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

  // The connections a drag of `moving` may snap to: every other block's, but insertion markers'.
  function neighbourConnections(moving) {
    const own = new Set(moving.getDescendants(false));
    const found = [];
    for (const block of blockly.workspace().getAllBlocks(false)) {
      if (own.has(block) || block.isInsertionMarker()) continue;
      for (const connection of block.getConnections_(false)) found.push(connection);
    }
    return found;
  }

  // Where `neighbours` are while Blockly previews `candidate` ({local, neighbour}): the drag strategy's
  // own choice of preview, drawn for real with events off and taken down again, as if a drag were in
  // progress (so that no script is bumped). An insertion marker pushes what follows it aside (by its
  // height less an empty mouth's, or its width in an input), and the next pointer move is matched
  // against the connections where the preview left them. Only a marker that hangs from the neighbour
  // is drawn: one above a stack (the dragged stack's last next connection) follows the pointer and
  // carries that stack with it, moving nothing that follows.
  function previewedPositions(moving, candidate, neighbours) {
    const SB = blockly.scratchBlocks();
    const ws = blockly.workspace();
    const {local, neighbour} = candidate;
    const positions = new Map();
    if (local.type !== OUTPUT_VALUE && local.type !== PREVIOUS_STATEMENT) return positions;
    if (neighbour.isConnected() && !neighbour.targetBlock().isInsertionMarker()) {
      const orphan = neighbour.targetBlock();
      const fits = SB.Connection.getConnectionForOrphanedConnection(moving, local.type === OUTPUT_VALUE ? orphan.outputConnection : orphan.previousConnection);
      if (!fits) return positions; // a replacement preview fades the block it would replace, and moves none
    }
    const Previewer = SB.registry.getClassFromOptions(SB.registry.Type.CONNECTION_PREVIEWER, ws.options, true);
    const previewer = new Previewer(moving);
    // Drawing and removing a preview may scroll the view (by tens of pixels); it goes back to where it
    // was, or the plan's page points would miss what they aim at.
    const [scrollX, scrollY] = [ws.scrollX, ws.scrollY];
    SB.Events.disable();
    try {
      blockly.asIfDragging(() => {
        try {
          previewer.previewConnection(local, neighbour);
          SB.renderManagement.triggerQueuedRenders(ws);
          for (const connection of neighbours) positions.set(connection, {x: connection.x, y: connection.y});
        } finally {
          previewer.hidePreview();
          previewer.dispose();
          SB.renderManagement.triggerQueuedRenders(ws);
        }
      });
    } finally {
      SB.Events.enable();
      if (ws.scrollX !== scrollX || ws.scrollY !== scrollY) ws.scroll(scrollX, scrollY);
    }
    return positions;
  }

  // Replays Blockly's choice of connection for a drag of `moving` by each of `deltas` (workspace
  // units from where the drag started) in turn: the drag strategy's closest candidate within the
  // snap radius (the larger connecting radius while it has one), kept over a new one that is not
  // `currentConnectionPreference` closer, each move matched against the connections as the previous
  // move's preview left them (what a drag drawn frame by frame sees). `visit(current, step)` sees each
  // step's candidate (null: none) and may stop the replay by returning false. Options: `neighbours`
  // (precomputed), `previews` (a cache of previewed positions per candidate, across replays of one
  // drag), `everyone` (the connections a preview's positions are recorded for, when `neighbours` is a
  // part of them: a shared preview cache must hold them all) and `localAt` (where each of the moving
  // block's connections is when the drag starts, when that is not where it is drawn). Returns the
  // last candidate: what a release there connects.
  function replayCandidates(moving, deltas, options) {
    const {visit, neighbours, previews, localAt, everyone} = options || {};
    const config = blockly.scratchBlocks().config;
    const checker = blockly.workspace().connectionChecker;
    const locals = localConnections(moving);
    const list = neighbours || neighbourConnections(moving);
    const cache = previews || new Map();
    const previewOf = (candidate) => {
      let byLocal = cache.get(candidate.local);
      if (!byLocal) cache.set(candidate.local, (byLocal = new Map()));
      let positions = byLocal.get(candidate.neighbour);
      if (!positions) byLocal.set(candidate.neighbour, (positions = previewedPositions(moving, candidate, everyone || list)));
      return positions;
    };
    let current = null;
    let shown = new Map();
    const distance = (local, delta, other) => {
      const from = (localAt && localAt.get(local)) || local;
      const at = shown.get(other) || other;
      return Math.hypot(from.x + delta.x - at.x, from.y + delta.y - at.y);
    };
    for (let i = 0; i < deltas.length; i++) {
      const delta = deltas[i];
      let best = null;
      let radius = current ? config.connectingSnapRadius : config.snapRadius;
      for (const local of locals) {
        for (const other of list) {
          if (other.type !== OPPOSITE[local.type]) continue;
          const d = distance(local, delta, other);
          if (d > radius || !checker.canConnect(local, other, true, Infinity)) continue;
          best = {local: local, neighbour: other, distance: d};
          radius = d;
        }
      }
      if (!best) current = null;
      else if (!current || !(best.distance > distance(current.local, delta, current.neighbour) - config.currentConnectionPreference)) current = best;
      shown = current ? previewOf(current) : new Map();
      if (visit && visit(current, i + 1) === false) break;
    }
    return current;
  }

  // Workspace units around a path within which a connection may become a candidate: the larger
  // snap radius, and room for a preview to push a connection towards the path.
  const PATH_REACH = 300;

  // The neighbours that a drag of `moving` by `deltas` can come near (the rest cannot be a
  // candidate on the way): a cheap filter that keeps long replays over many spots affordable.
  function nearPath(moving, deltas, neighbours) {
    const xs = deltas.map((d) => d.x);
    const ys = deltas.map((d) => d.y);
    const [x0, x1, y0, y1] = [Math.min(0, ...xs), Math.max(0, ...xs), Math.min(0, ...ys), Math.max(0, ...ys)];
    const boxes = localConnections(moving).map((c) => ({x0: c.x + x0 - PATH_REACH, x1: c.x + x1 + PATH_REACH, y0: c.y + y0 - PATH_REACH, y1: c.y + y1 + PATH_REACH}));
    return neighbours.filter((n) => boxes.some((b) => n.x >= b.x0 && n.x <= b.x1 && n.y >= b.y0 && n.y <= b.y1));
  }

  // How a straight path ends: `clean` when no connection but the wanted one is ever the candidate (no
  // preview can move the wanted connection away, and the drop ends on it); with `full`, also whether
  // it `lands`: the candidate at the release is the wanted one, whatever came first on the way (other
  // candidates' previews are replayed as drawn), also for a release `margin` units off in every
  // direction (against rounding and a preview drawn slightly otherwise than replayed).
  function simulatePath(moving, deltas, wanted, options) {
    const {neighbours, previews, margin, full} = options || {};
    const same = (c) => !!c && c.local === wanted.local && c.neighbour === wanted.neighbour;
    const everyone = neighbours || neighbourConnections(moving);
    const near = nearPath(moving, deltas, everyone);
    let unclean = null;
    const last = replayCandidates(moving, deltas, {neighbours: near, everyone: everyone, previews: previews, visit: (current, step) => {
      if (current && !same(current) && !unclean) unclean = {step: step, candidate: describeConnection(current.neighbour)};
      return !unclean || !!full;
    }});
    if (!unclean && last) return {clean: true, lands: true};
    const result = unclean
      ? {clean: false, step: unclean.step, candidate: unclean.candidate}
      : {clean: false, step: deltas.length, candidate: null};
    result.lands = !!full && same(last);
    if (result.lands && margin) {
      const end = deltas[deltas.length - 1];
      for (const [dx, dy] of [[margin, 0], [-margin, 0], [0, margin], [0, -margin]]) {
        const moved = deltas.slice(0, -1).concat([{x: end.x + dx, y: end.y + dy}]);
        if (!same(replayCandidates(moving, moved, {neighbours: near, everyone: everyone, previews: previews}))) {
          result.lands = false;
          break;
        }
      }
    }
    return result;
  }

  function mousePath(start, end, steps) {
    const points = [];
    for (let i = 1; i <= steps; i++) points.push({x: start.x + (end.x - start.x) * i / steps, y: start.y + (end.y - start.y) * i / steps});
    return points;
  }

  // Margin (workspace units) a landing release must keep: a release this far off must land too.
  const LANDING_MARGIN = 3;
  // Staging spots tried: the nearest free places to the destination on the fine grid, then free places
  // all over the view on a coarser one, nearest first.
  const NEAR_SPOTS = 400;
  const STAGING_GRID = 16;
  const STAGING_SPOTS = 1500;
  const LANDING_SPOTS = 200;

  // How to drag `moving` so that its connection `local` meets connection `remote` of `target`:
  // the press and release points, whether the straight path snaps only to the wanted connection
  // (`clean`) or at least ends on it (`lands`), and if not clean, a free spot to move the block to
  // first from where the path is clean (or, when no spot gives a clean path, one where it lands).
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
    if (!grab || !plan.endVisible) return Object.assign(plan, {clean: false, lands: false, reason: 'out of view'});
    const wanted = {local: local, neighbour: remote};
    const options = {neighbours: neighbourConnections(moving), previews: new Map(), margin: LANDING_MARGIN, full: true};
    const toDeltas = (start) => mousePath(start, end, steps).map((p) => ({x: (p.x - grab.x) / scale, y: (p.y - grab.y) / scale}));
    const direct = simulatePath(moving, toDeltas(grab), wanted, options);
    plan.lands = direct.lands;
    if (direct.clean) return Object.assign(plan, {clean: true});
    plan.clean = false;
    plan.reason = direct.candidate ? `the path meets ${direct.candidate} first (mouse step ${direct.step})` : 'the drop does not reach the connection';
    // Staging spots: free places for the block, nearest to the destination first; a clean path wins,
    // else the first spot (of the nearest LANDING_SPOTS) whose path lands.
    const ignore = moving.getParent() ? [] : [moving.id];
    const spots = freeSpots(rect.width, rect.height, ignore, remotePage, NEAR_SPOTS)
      .concat(freeSpots(rect.width, rect.height, ignore, remotePage, STAGING_SPOTS, STAGING_GRID))
      .map((spot) => ({spot: spot, start: {x: spot.x + grab.x - rect.x, y: spot.y + grab.y - rect.y}}))
      .filter(({start}) => Math.hypot(start.x - end.x, start.y - end.y) >= 4);
    const strict = Object.assign({}, options, {full: false});
    for (const {spot, start} of spots) {
      if (simulatePath(moving, toDeltas(start), wanted, strict).clean) {
        plan.staging = {spot: spot, end: start, clean: true};
        return plan;
      }
    }
    let landing = null;
    for (const {spot, start} of spots.slice(0, LANDING_SPOTS)) {
      if (simulatePath(moving, toDeltas(start), wanted, options).lands) {
        landing = {spot: spot, end: start, clean: false};
        break;
      }
    }
    if (landing) plan.staging = landing;
    return plan;
  }

  return {
    connectionNamed: connectionNamed, describeConnection: describeConnection, localConnections: localConnections, neighbourConnections: neighbourConnections,
    replayCandidates: replayCandidates,
    api: {geometryFreeSpot: (args) => freeSpot(args), geometryPlanDrag: (args) => planDrag(args)},
  };
}});
