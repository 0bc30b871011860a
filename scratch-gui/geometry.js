/*
 * Geometry: privileged, read-only views of the editor's layout in page pixels, for scripted agents
 * that act only through real mouse and keyboard gestures (the primitive oracle).
 *
 * Nothing here writes to the VM or the workspace. Every function reads live state: where blocks,
 * their connections and fields are drawn, what the palette (flyout) shows, which menu, text
 * editor or modal is open, where an empty spot of the workspace is, and a semantic snapshot of the
 * project (scripts without ids or positions) to compare two ways of reaching the same state.
 * `geometryWait` waits, bounded, for a named condition after a gesture (the palette finished its
 * scroll animation, a menu is open and still, a new block arrived in the VM, ...), so callers
 * never sleep for a fixed time.
 */
(function () {
  'use strict';

  const DEFAULT_WAIT_MS = 5000;
  const MAX_WAIT_MS = 30000;
  const POLL_MS = 10;
  // A rect or scroll position must be unchanged for this many polls to count as still.
  const STILL_POLLS = 2;
  // Inset of the usable workspace from its visible edges (scrollbars, zoom buttons live there).
  const EDGE = 12;
  const SCROLLBAR = 14;
  const GRID = 8;
  // Connection types of Blockly: input value, output, next statement, previous statement.
  const INPUT_VALUE = 1;
  const NEXT_STATEMENT = 3;

  function factory(ctx) {
    const fail = (message) => new ctx.BridgeFailure('bad_request', message);

    function component() {
      return ctx.blocksComponent();
    }

    function scratchBlocks() {
      return component().ScratchBlocks;
    }

    function workspace() {
      return component().workspace;
    }

    function flyout() {
      const theFlyout = workspace().getFlyout();
      if (!theFlyout) throw new ctx.BridgeFailure('editor_not_ready', 'the palette (flyout) is not rendered');
      return theFlyout;
    }

    /* ---------- rects and points ---------- */

    function rectOf(element) {
      const r = element.getBoundingClientRect();
      return {x: r.left, y: r.top, width: r.width, height: r.height};
    }

    const right = (r) => r.x + r.width;
    const bottom = (r) => r.y + r.height;
    const centre = (r) => ({x: r.x + r.width / 2, y: r.y + r.height / 2});
    const inside = (r, x, y) => x >= r.x && x <= right(r) && y >= r.y && y <= bottom(r);
    const overlaps = (a, b) => a.x < right(b) && b.x < right(a) && a.y < bottom(b) && b.y < bottom(a);
    const grow = (r, by) => ({x: r.x - by, y: r.y - by, width: r.width + 2 * by, height: r.height + 2 * by});

    function clip(r, bounds) {
      const x = Math.max(r.x, bounds.x);
      const y = Math.max(r.y, bounds.y);
      return {x: x, y: y, width: Math.max(0, Math.min(right(r), right(bounds)) - x), height: Math.max(0, Math.min(bottom(r), bottom(bounds)) - y)};
    }

    function viewport() {
      return {x: 0, y: 0, width: window.innerWidth, height: window.innerHeight};
    }

    // Workspace coordinates of `ws` to page pixels, through the canvas's current transform.
    function toPage(ws, x, y) {
      const m = ws.getCanvas().getScreenCTM();
      return {x: m.a * x + m.c * y + m.e, y: m.b * x + m.d * y + m.f};
    }

    // The part of the main workspace that is visible on the page (right of the palette).
    function workspaceView() {
      const ws = workspace();
      const svg = ws.getParentSvg().getBoundingClientRect();
      const metrics = ws.getMetrics();
      const view = {x: svg.left + metrics.absoluteLeft, y: svg.top + metrics.absoluteTop, width: metrics.viewWidth, height: metrics.viewHeight};
      return clip(view, viewport());
    }

    // Where blocks may be dropped and grabbed: the visible workspace without its edges and scrollbars.
    function safeArea() {
      const view = workspaceView();
      return {x: view.x + EDGE, y: view.y + EDGE, width: view.width - 2 * EDGE - SCROLLBAR, height: view.height - 2 * EDGE - SCROLLBAR};
    }

    // Things drawn over the workspace that a dropped block must not land under.
    function overlays() {
      const found = [];
      for (const element of document.querySelectorAll('.blocklyZoom, [class*="watermark"]')) {
        const r = rectOf(element);
        if (r.width > 0 && r.height > 0) found.push(r);
      }
      return found;
    }

    function flyoutView() {
      const element = document.querySelector('.blocklyFlyout');
      if (!element) throw new ctx.BridgeFailure('editor_not_ready', 'the palette (flyout) is not rendered');
      return clip(rectOf(element), viewport());
    }

    /* ---------- blocks ---------- */

    function liveBlock(id) {
      if (typeof id !== 'string' || !id) throw fail('id must be a non-empty string');
      const block = workspace().getBlockById(id);
      if (!block) throw new ctx.BridgeFailure('not_found', `no block ${JSON.stringify(id)} in the visible workspace`);
      return block;
    }

    function connectionAt(ws, connection) {
      if (!connection) return null;
      const point = toPage(ws, connection.x, connection.y);
      point.connected = !!connection.targetConnection;
      return point;
    }

    // A point on the block's own body (not a child block, not an editable field) that a press
    // hits, scanning from the left edge; null when no such point is visible inside `area`.
    function grabPoint(ws, block, area) {
      const r = rectOf(block.getSvgRoot());
      const canvas = ws.getCanvas();
      for (let x = Math.ceil(r.x + 2); x < right(r) - 1; x += 3) {
        for (let y = Math.ceil(r.y + 2); y < bottom(r) - 1; y += 3) {
          if (!inside(area, x, y)) continue;
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
      const ws = workspace();
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
        rect: rectOf(block.getSvgRoot()),
        grab: grabPoint(ws, block, safeArea()),
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
      const dropdown = typeof field.getOptions === 'function';
      let options = null;
      if (dropdown) {
        try {
          options = field.getOptions(false).map((option) => ({text: optionText(option), value: String(option[1])}));
        } catch (e) {
          options = [];
        }
      }
      const root = field.getSvgRoot();
      return {
        kind: dropdown ? 'dropdown' : 'text',
        name: field.name,
        value: field.getValue() === null ? null : String(field.getValue()),
        text: field.getText(),
        rect: root ? rectOf(root) : null,
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
      const theFlyout = flyout();
      return {scrollY: theFlyout.getWorkspace().scrollY, animating: theFlyout.scrollTarget !== undefined};
    }

    function flyoutBlock(args) {
      if (typeof args.opcode !== 'string') throw fail('opcode must be a string');
      const theFlyout = flyout();
      const fws = theFlyout.getWorkspace();
      const view = flyoutView();
      const candidates = fws.getTopBlocks(false).filter((b) => b.type === args.opcode);
      const wanted = args.variableName;
      const block = candidates.find((b) => {
        if (typeof wanted !== 'string') return true;
        const field = b.getField('VARIABLE') || b.getField('LIST');
        return !!field && field.getText() === wanted;
      });
      if (!block) return {found: false, count: candidates.length, flyout: view};
      const rect = rectOf(block.getSvgRoot());
      return {
        found: true,
        id: block.id,
        rect: rect,
        visible: rect.y >= view.y && bottom(rect) <= bottom(view) - 2,
        grab: grabPoint(fws, block, view),
        flyout: view,
        flyoutScale: fws.scale,
        workspaceScale: workspace().scale
      };
    }

    function flyoutButton(args) {
      const view = flyoutView();
      for (const element of document.querySelectorAll('.blocklyFlyout .blocklyFlyoutButton')) {
        if (element.textContent.trim() !== args.text) continue;
        const rect = rectOf(element);
        return {found: true, rect: rect, visible: rect.y >= view.y && bottom(rect) <= bottom(view) - 2, flyout: view};
      }
      return {found: false, flyout: view};
    }

    /* ---------- the page around the workspace ---------- */

    function categories() {
      return [...document.querySelectorAll('.blocklyToolboxCategory')].map((element) => ({
        name: element.textContent.trim(),
        rect: rectOf(element),
        selected: element.classList.contains('blocklyToolboxSelected')
      }));
    }

    function targetTiles() {
      const sprites = [...document.querySelectorAll('[class*="sprite-selector_sprite-wrapper"]')].map((element) => {
        const label = element.querySelector('[class*="sprite-selector-item_sprite-name"]');
        return {name: (label || element).textContent.trim(), rect: rectOf(element)};
      });
      const stageElement = document.querySelector('[class*="stage-selector_stage-selector"]');
      return {sprites: sprites, stage: stageElement ? rectOf(stageElement) : null};
    }

    function layout() {
      const ws = workspace();
      const vm = ctx.requireVm();
      return {
        workspace: workspaceView(),
        safeArea: safeArea(),
        overlays: overlays(),
        flyout: flyoutView(),
        scale: ws.scale,
        snapRadius: scratchBlocks().config.snapRadius,
        connectingSnapRadius: scratchBlocks().config.connectingSnapRadius,
        categories: categories(),
        targets: targetTiles(),
        editingTarget: vm.editingTarget ? vm.editingTarget.getName() : null,
        viewport: viewport()
      };
    }

    /* ---------- dropdowns, text editors, modals ---------- */

    function shown(element) {
      if (!element) return false;
      const style = getComputedStyle(element);
      const r = element.getBoundingClientRect();
      return style.display !== 'none' && style.visibility !== 'hidden' && r.width > 0 && r.height > 0;
    }

    // The open menu: a field's dropdown (DropDownDiv) or a context menu (WidgetDiv).
    function menu() {
      const holders = [document.querySelector('.blocklyDropDownDiv'), document.querySelector('.blocklyWidgetDiv')];
      const holder = holders.find((div) => div && shown(div.querySelector('.blocklyMenuItem')));
      if (!holder) return {open: false, items: [], rect: null};
      const box = holder.querySelector('.blocklyMenu');
      const items = [...holder.querySelectorAll('.blocklyMenuItem')].map((element) => {
        const rect = rectOf(element);
        const c = centre(rect);
        const hit = document.elementFromPoint(c.x, c.y);
        const content = element.querySelector('.blocklyMenuItemContent') || element;
        return {text: content.textContent.trim(), rect: rect, visible: !!hit && hit.closest('.blocklyMenuItem') === element};
      });
      return {open: true, items: items, rect: rectOf(box)};
    }

    function textEditor() {
      const input = document.querySelector('.blocklyWidgetDiv .blocklyHtmlInput');
      return {open: shown(input), focused: !!input && document.activeElement === input, value: input ? input.value : null};
    }

    function modal() {
      const content = document.querySelector('.ReactModal__Content');
      if (!shown(content)) return {open: false};
      const title = content.querySelector('[class*="modal_header-item-title"]');
      return {
        open: true,
        title: title ? title.textContent.trim() : '',
        inputs: [...content.querySelectorAll('input[type="text"], input:not([type])')].filter(shown).map((input) => ({
          rect: rectOf(input), value: input.value, focused: document.activeElement === input
        })),
        options: [...content.querySelectorAll('label')].filter((label) => label.querySelector('input[type="radio"]') && shown(label)).map((label) => ({
          text: label.textContent.trim(), rect: rectOf(label), checked: label.querySelector('input[type="radio"]').checked
        })),
        buttons: [...content.querySelectorAll('button')].filter(shown).map((button) => ({text: button.textContent.trim(), rect: rectOf(button)}))
      };
    }

    /* ---------- empty space ---------- */

    // Top-left corners (page pixels) of free width x height boxes inside the usable workspace,
    // farther than any snap radius from every block (but those in `ignore`), nearest to `near` first.
    function freeSpots(width, height, ignore, near, limit) {
      const ws = workspace();
      const area = safeArea();
      const config = scratchBlocks().config;
      const margin = Math.max(config.snapRadius, config.connectingSnapRadius) * ws.scale + GRID;
      const obstacles = ws.getTopBlocks(false).filter((b) => !ignore.includes(b.id)).map((b) => grow(rectOf(b.getSvgRoot()), margin));
      for (const r of overlays()) obstacles.push(grow(r, GRID));
      const from = near || {x: area.x, y: area.y};
      const spots = [];
      for (let y = area.y; y + height <= bottom(area); y += GRID) {
        for (let x = area.x; x + width <= right(area); x += GRID) {
          const box = {x: x, y: y, width: width, height: height};
          if (!obstacles.some((o) => overlaps(o, box))) spots.push({x: x, y: y, d: Math.hypot(x - from.x, y - from.y)});
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
      return {spot: spots.length ? spots[0] : null, area: safeArea()};
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
      const ws = workspace();
      const config = scratchBlocks().config;
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
      const ws = workspace();
      const moving = liveBlock(args.moving);
      const target = liveBlock(args.target);
      const local = connectionNamed(moving, args.local);
      const remote = connectionNamed(target, args.remote);
      if (!local) throw new ctx.BridgeFailure('not_found', `${moving.type} has no ${args.local} connection`);
      if (!remote) throw new ctx.BridgeFailure('not_found', `${target.type} has no ${args.remote} connection`);
      const steps = Math.max(1, Number(args.steps) || 10);
      const area = safeArea();
      const scale = ws.scale;
      const rect = rectOf(moving.getSvgRoot());
      const localPage = toPage(ws, local.x, local.y);
      const remotePage = toPage(ws, remote.x, remote.y);
      const grab = grabPoint(ws, moving, area);
      const reference = grab || centre(rect);
      const end = {x: reference.x + remotePage.x - localPage.x, y: reference.y + remotePage.y - localPage.y};
      const plan = {grab: grab, end: end, rect: rect, reference: reference, endVisible: inside(area, end.x, end.y)};
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

    /* ---------- semantic snapshot ---------- */

    function chainOf(blocks, id) {
      const chain = [];
      for (let cursor = id; cursor;) {
        const block = blocks.getBlock(cursor);
        if (!block) break;
        const fields = {};
        for (const name of Object.keys(block.fields).sort()) fields[name] = String(block.fields[name].value);
        const inputs = {};
        for (const name of Object.keys(block.inputs).sort()) {
          const input = block.inputs[name];
          if (input.block) inputs[name] = chainOf(blocks, input.block);
        }
        chain.push({opcode: block.opcode, shadow: !!block.shadow, fields: fields, inputs: inputs});
        cursor = block.next;
      }
      return chain;
    }

    // Per target: its variables and lists (names), and its scripts as id- and position-free
    // trees, sorted, so two projects built differently compare equal when they mean the same.
    function snapshot() {
      const vm = ctx.requireVm();
      const targets = vm.runtime.targets.filter((t) => t.isOriginal).map((target) => {
        const variables = Object.values(target.variables)
          .filter((v) => v.type === '' || v.type === 'list')
          .map((v) => `${v.type || 'variable'}:${v.name}`)
          .sort();
        const scripts = target.blocks.getScripts()
          .map((id) => target.blocks.getBlock(id))
          .filter((b) => b && !b.shadow)
          .map((b) => JSON.stringify(chainOf(target.blocks, b.id)))
          .sort();
        return {name: target.getName(), isStage: target.isStage, variables: variables, scripts: scripts};
      });
      return {editingTarget: vm.editingTarget ? vm.editingTarget.getName() : null, targets: targets};
    }

    // Every non-shadow block of every target by a structural path ("Target/script/position/INPUT/...",
    // scripts ordered by position then content): ids of compact blocks (variable reporters) are new
    // on every load of a project, paths are not.
    function blockPaths() {
      const vm = ctx.requireVm();
      const paths = {};
      for (const target of vm.runtime.targets.filter((t) => t.isOriginal)) {
        const blocks = target.blocks;
        const own = paths[target.getName()] = {};
        const visit = (id, path) => {
          let n = 0;
          for (let cursor = id; cursor; n++) {
            const block = blocks.getBlock(cursor);
            if (!block) break;
            const here = `${path}/${n}`;
            if (!block.shadow) own[block.id] = here;
            for (const name of Object.keys(block.inputs).sort()) {
              const input = block.inputs[name];
              if (input.block) visit(input.block, `${here}/${name}`);
            }
            cursor = block.next;
          }
        };
        blocks.getScripts().map((id) => blocks.getBlock(id)).filter((b) => b && !b.shadow)
          .map((b) => ({id: b.id, x: Number(b.x) || 0, y: Number(b.y) || 0, key: JSON.stringify(chainOf(blocks, b.id))}))
          .sort((a, b) => a.y - b.y || a.x - b.x || (a.key < b.key ? -1 : a.key > b.key ? 1 : 0))
          .forEach((top, k) => visit(top.id, `${target.getName()}/${k}`));
      }
      return {paths: paths};
    }

    function topBlocks() {
      const target = ctx.requireVm().editingTarget;
      if (!target) return {vm: [], workspace: []};
      const vmTops = target.blocks.getScripts().map((id) => target.blocks.getBlock(id)).filter((b) => b && !b.shadow)
        .map((b) => ({id: b.id, opcode: b.opcode}));
      const wsTops = workspace().getTopBlocks(false).map((b) => ({id: b.id, opcode: b.type}));
      return {vm: vmTops, workspace: wsTops};
    }

    /* ---------- bounded waits ---------- */

    function dragging() {
      const ws = workspace();
      return typeof ws.isDragging === 'function' && ws.isDragging();
    }

    // True when the workspace shows exactly the editing target's scripts and nothing is moving.
    function workspaceInSync() {
      if (dragging()) return false;
      const tops = topBlocks();
      const a = tops.vm.map((b) => b.id).sort().join('\n');
      const b = tops.workspace.map((b) => b.id).sort().join('\n');
      return a === b;
    }

    // Each condition returns {done, value}; `still` conditions also need `value` to stay the same.
    const CONDITIONS = {
      flyoutSettled: {still: true, check: () => {
        const state = flyoutState();
        return {done: !state.animating, value: state.scrollY};
      }},
      editingTarget: {still: true, check: (args) => {
        const vm = ctx.requireVm();
        const name = vm.editingTarget ? vm.editingTarget.getName() : null;
        const state = flyoutState();
        return {done: name === args.name && workspaceInSync() && !state.animating, value: `${name}|${state.scrollY}`};
      }},
      menuOpen: {still: true, check: () => {
        const state = menu();
        // Still means placed (the div may animate in) and not scrolling (its items move).
        return {done: state.open, value: state.open ? JSON.stringify([state.rect, state.items.length ? state.items[0].rect : null]) : null};
      }},
      menuClosed: {still: false, check: () => ({done: !menu().open, value: null})},
      textEditorOpen: {still: false, check: () => {
        const state = textEditor();
        return {done: state.open && state.focused, value: null};
      }},
      textEditorClosed: {still: false, check: () => ({done: !textEditor().open, value: null})},
      modalOpen: {still: true, check: () => {
        const state = modal();
        return {done: state.open && state.inputs.length > 0, value: state.open ? JSON.stringify(state.inputs.map((i) => i.rect)) : null};
      }},
      modalClosed: {still: false, check: () => ({done: !modal().open, value: null})},
      // A new top-level block of `opcode` (not one of `known`) is in the VM and the workspace.
      newBlock: {still: false, check: (args) => {
        const known = new Set(args.known || []);
        const fresh = topBlocks().vm.filter((b) => b.opcode === args.opcode && !known.has(b.id));
        const ok = fresh.length === 1 && workspaceInSync();
        return {done: ok, value: ok ? fresh[0].id : fresh.map((b) => b.id)};
      }},
      inSync: {still: false, check: () => ({done: workspaceInSync(), value: null})},
      // The VM (which learns of edits asynchronously) holds `value` in a field or input of a block.
      blockValue: {still: false, check: (args) => {
        const values = blockFields({id: args.id})[args.kind] || {};
        return {done: values[args.name] === args.value, value: values[args.name] === undefined ? null : values[args.name]};
      }},
      snapshot: {still: false, check: (args) => {
        const current = snapshot();
        return {done: !dragging() && JSON.stringify(current) === args.expected, value: current};
      }},
      // Nothing moves: no drag, the workspace shows the VM's scripts, palette and workspace are still.
      quiet: {still: true, check: () => {
        const ws = workspace();
        const state = flyoutState();
        const first = flyout().getWorkspace().getTopBlocks(false)[0];
        return {done: workspaceInSync() && !state.animating, value: `${ws.scrollX}|${ws.scrollY}|${state.scrollY}|${first ? first.id : ''}`};
      }}
    };

    async function wait(args) {
      const condition = CONDITIONS[args.until];
      if (!condition) throw fail(`unknown condition ${JSON.stringify(args.until)}; conditions: ${Object.keys(CONDITIONS).join(', ')}`);
      const timeoutMs = Math.min(Number(args.timeoutMs) || DEFAULT_WAIT_MS, MAX_WAIT_MS);
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

    return {
      geometryLayout: () => layout(),
      geometryBlock: (args) => blockInfo(args),
      geometryField: (args) => fieldInfo(args),
      geometryBlockFields: (args) => blockFields(args),
      geometryFlyoutBlock: (args) => flyoutBlock(args),
      geometryFlyoutButton: (args) => flyoutButton(args),
      geometryMenu: () => menu(),
      geometryTextEditor: () => textEditor(),
      geometryModal: () => modal(),
      geometryFreeSpot: (args) => freeSpot(args),
      geometryPlanDrag: (args) => planDrag(args),
      geometryTopBlocks: () => topBlocks(),
      geometryBlockPaths: () => blockPaths(),
      geometrySnapshot: () => {
        const state = snapshot();
        return {state: state, text: JSON.stringify(state)};
      },
      geometryWait: (args) => wait(args)
    };
  }

  const modules = window.__scratchworldModules = window.__scratchworldModules || [];
  modules.push(factory);
})();
