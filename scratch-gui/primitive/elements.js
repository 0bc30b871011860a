/*
 * Primitive mode, page side: the indexed element list an agent reads next to its screenshot.
 *
 * `primitiveElements` walks the DOM once, synchronously, and returns
 *   elements:     what a user can see and point at, in document order (the flyout's contents in
 *                 layout order), each {type, text, x, y, width, height, opcode?, blockId?, where?}
 *                 with an integer page-pixel rect (x, y top-left) clipped to the area it is drawn
 *                 in; kept only when the centre of that rect hit-tests to the element itself, so
 *                 whatever a modal, a dropdown or the flyout covers is not listed;
 *   textBoxes:    the text drawn in canvas blocks, which the DOM knows exactly (no OCR needed);
 *   pixelRegions: where text exists only as pixels (the stage, other canvases, pictures), the
 *                 only places worth running OCR on.
 * Selectors are Blockly class names, roles, data attributes or CSS-module *name* prefixes
 * (`[class*="sprite-selector_sprite-wrapper"]`), never the module hashes, which change with
 * every GUI build. Blocks are named through the Blockly API, never from their ids.
 * The wait that makes the screenshot worth reading is the page's one settle rule (shared/settle.js).
 */
scratchworldModule({name: 'primitive/elements', requires: ['rects', 'blockly', 'settle'], create(ctx, rects, blockly, settle) {
  'use strict';

  const MAX_TEXT = 200;
  const MIN_IMAGE_SIDE = 24;
  // A role=button no larger than this holding a picture is an icon button, not a tile.
  const MAX_ICON_BUTTON = 48;

  // Menus: Blockly dropdowns and context menus, the GUI's menu-bar menus and Radix menus.
  const DROPDOWN_ITEMS = '.blocklyMenuItem, .goog-menuitem, [data-menu-item="true"], [role="menuitem"], ' +
    '[role="menuitemradio"], [role="menuitemcheckbox"], [role="option"]';
  const MENU_BAR_ITEM = '[class*="menu-bar_menu-bar-item"]';
  const STAGE_HEADER = '[class*="stage-header_stage-header-wrapper"]';
  const SPRITE_TILE = '[class*="sprite-selector_sprite-wrapper"]';
  const STAGE_SELECTOR = '[class*="stage-selector_stage-selector_"]';

  // How a claimed element treats the matches inside it: 'all' hides them; 'buttons' lets real
  // <button>s through (a sprite tile's delete button, the stage selector's add-backdrop menu);
  // 'menus' lets menu items through (an open menu inside its menu-bar item, submenus); 'none'
  // hides nothing (blocks hold blocks and fields).
  const ABSORB = {
    dropdown_items: 'menus', menu: 'menus', tabs: 'all', green_flag: 'all', stop: 'all', stage_buttons: 'all',
    stage: 'all', category_menu_item: 'all', flyout_buttons: 'all', flyout_label: 'all', blocks: 'none',
    fields: 'all', canvas: 'all', inputs: 'all', sprites: 'buttons', stage_selector: 'buttons', buttons: 'buttons',
  };

  // One query, so the list comes in document order. (Buttons in the menu bar and the stage
  // header are typed by where they sit, see classifyHtml.)
  const CANDIDATES = [
    DROPDOWN_ITEMS, MENU_BAR_ITEM, '[role="tab"]', '[class*="green-flag_green-flag"]', '[class*="stop-all_stop-all"]', 'canvas',
    '.blocklyToolboxCategory', '.scratchCategoryMenuItem', '.blocklyFlyoutButton', '.blocklyFlyoutLabel',
    '.blocklyDraggable', '.blocklySvg .blocklyEditableField', '.blocklyFlyoutCheckbox', '.blocklyMainBackground', '.blocklyZoom',
    'input', 'textarea', SPRITE_TILE, STAGE_SELECTOR, 'button', '[role="button"]',
  ].join(', ');

  function clean(value) {
    return String(value == null ? '' : value).replace(/[\s\u00a0]+/g, ' ').trim().slice(0, MAX_TEXT);
  }

  function firstLine(value) {
    return clean(String(value == null ? '' : value).split('\n').find((line) => line.trim()) || '');
  }

  // What a user reads on (or hears for) an element: its text, else its label, else its icon's.
  // A menu item's first line is its own text; the lines below belong to its submenu.
  function label(el, firstOnly) {
    const text = el.innerText !== undefined ? el.innerText : el.textContent;
    let found = (firstOnly ? firstLine(text) : clean(text)) || clean(el.getAttribute('aria-label')) || clean(el.getAttribute('title'));
    if (!found) {
      const icon = el.querySelector('img[alt]:not([alt=""]), img[title], [aria-label]');
      if (icon) found = clean(icon.getAttribute('alt') || icon.getAttribute('title') || icon.getAttribute('aria-label'));
    }
    return found;
  }

  function quoted(value) {
    return JSON.stringify(String(value).slice(0, MAX_TEXT));
  }

  // `name value: "v" placeholder: "p"`, naming the field after whatever labels it.
  function describeInput(el) {
    const placeholder = el.getAttribute('placeholder') || '';
    const labels = el.labels ? Array.from(el.labels).map((l) => clean(l.innerText)).filter(Boolean) : [];
    const name = clean(el.getAttribute('aria-label')) || clean(el.getAttribute('name')) || labels[0] ||
      clean(el.getAttribute('title')) || clean(placeholder);
    const parts = name ? [name] : [];
    parts.push(`value: ${quoted(el.value == null ? '' : el.value)}`);
    if (placeholder && clean(placeholder) !== name) parts.push(`placeholder: ${quoted(placeholder)}`);
    return parts.join(' ');
  }

  function describeChoice(el) {
    const labels = el.labels ? Array.from(el.labels).map((l) => clean(l.innerText)).filter(Boolean) : [];
    const name = labels[0] || clean(el.getAttribute('aria-label')) || clean(el.getAttribute('value'));
    return `${el.type} ${name} (${el.checked ? 'checked' : 'unchecked'})`;
  }

  // --- Blockly ---------------------------------------------------------------------------------

  // What the DOM pass needs to know from Blockly: the code area's rect and the flyout's checkboxes.
  function blocklyState() {
    const state = blockly.drawn();
    if (!state) return null;
    const ws = state.ws;
    state.view = null;
    try {
      const svg = ws.getParentSvg().getBoundingClientRect();
      const metrics = ws.getMetricsManager();
      const abs = metrics.getAbsoluteMetrics();
      const size = metrics.getViewMetrics();
      state.view = rects.intersection(svg, {x: svg.left + abs.left, y: svg.top + abs.top, width: size.width, height: size.height});
    } catch (e) {
      state.view = null;
    }
    // The flyout's monitor checkboxes are bubbles of their blocks.
    state.checkboxes = new Map();
    if (state.flyoutWs) {
      for (const block of state.flyoutWs.getTopBlocks(false)) {
        for (const icon of block.icons || []) {
          const bubble = icon.checkboxBubble;
          if (bubble && bubble.getSvgRoot) state.checkboxes.set(bubble.getSvgRoot(), {block: block, bubble: bubble});
        }
      }
    }
    state.flyoutSvg = state.flyoutWs && state.flyoutWs.getParentSvg ? state.flyoutWs.getParentSvg() : null;
    return state;
  }

  function workspaceOf(state, el) {
    const group = el.closest('.blocklyWorkspace');
    if (!group) return null;
    if (group.id === state.ws.id) return state.ws;
    if (state.flyoutWs && group.id === state.flyoutWs.id) return state.flyoutWs;
    try {
      return state.SB.Workspace.getById(group.id) || null;
    } catch (e) {
      return null;
    }
  }

  function blockLabel(block, inFlyout) {
    if (!inFlyout) return `${block.type} on canvas`;
    const field = block.type === 'data_variable' ? block.getField('VARIABLE') : block.type === 'data_listcontents' ? block.getField('LIST') : null;
    if (field) return `${block.type} ${quoted(clean(field.getText()))}`;
    if (block.type === 'procedures_call' && typeof block.getProcCode === 'function') {
      return `${block.type} ${quoted(clean(block.getProcCode()))}`;
    }
    return block.type;
  }

  function ownPath(group) {
    const first = group.firstElementChild;
    const isPath = (node) => node && node.tagName === 'path' && (node.classList.contains('blocklyPath') || node.classList.contains('blocklyBlockBackground'));
    if (isPath(first)) return first;
    return Array.from(group.children).find(isPath) || null;
  }

  function fieldOf(block, el) {
    for (const input of block.inputList || []) {
      for (const field of input.fieldRow || []) {
        if (field.getSvgRoot && field.getSvgRoot() === el) return field;
      }
    }
    return null;
  }

  // --- classification --------------------------------------------------------------------------

  // Each candidate becomes {type, text, rect?, root?, area?, flyout?, block?, extra?} or null:
  // `rect` when the element's own box is not its target, `root` the subtree its centre must hit,
  // `area` what clips it (the viewport by default).
  function classify(el, env) {
    return el instanceof SVGElement ? classifySvg(el, env) : classifyHtml(el, env);
  }

  function classifySvg(el, env) {
    const state = env.blockly;
    if (!state) return null;
    const classes = el.classList;
    if (classes.contains('blocklyDraggable')) {
      // Most candidates are blocks, most of them scrolled out of the flyout: look at the box first.
      const path = ownPath(el);
      const ws = path && workspaceOf(state, el);
      if (!ws) return null;
      const inFlyout = !!ws.isFlyout;
      const area = inFlyout ? env.flyoutArea : env.workspaceArea;
      const rect = path.getBoundingClientRect();
      if (!area || !rects.intersection(rect, area)) return null;
      const block = ws.getBlockById(el.getAttribute('data-id'));
      if (!block || block.isShadow() || (block.isInsertionMarker && block.isInsertionMarker())) return null;
      return {type: 'blocks', text: blockLabel(block, inFlyout), rect: rect, area: area, flyout: inFlyout, block: true,
        extra: {opcode: block.type, blockId: block.id, where: inFlyout ? 'flyout' : 'canvas'}};
    }
    if (classes.contains('blocklyEditableField')) {
      const ws = workspaceOf(state, el);
      if (!ws || ws.isFlyout || !env.workspaceArea) return null;
      const owner = el.closest('.blocklyBlock[data-id]');
      const block = owner && ws.getBlockById(owner.getAttribute('data-id'));
      const field = block && fieldOf(block, el);
      if (!field) return null;
      // A shadow holding just this field (a number oval, a menu) is the field's visible target.
      const whole = block.isShadow() && block.inputList.reduce((n, input) => n + input.fieldRow.length, 0) === 1;
      const path = whole ? ownPath(owner) : null;
      return {type: 'fields', text: clean(field.getText()), rect: (path || el).getBoundingClientRect(),
        root: path ? owner : el, area: env.workspaceArea, extra: {blockId: block.id, where: 'canvas'}};
    }
    if (classes.contains('blocklyFlyoutButton')) {
      return {type: 'flyout_buttons', text: clean(el.textContent), area: env.flyoutArea, flyout: true};
    }
    if (classes.contains('blocklyFlyoutLabel')) {
      return {type: 'flyout_label', text: clean(el.textContent), area: env.flyoutArea, flyout: true};
    }
    if (classes.contains('blocklyFlyoutCheckbox')) {
      let node = el;
      for (let i = 0; node && i < 4 && !state.checkboxes.has(node); i++) node = node.parentNode;
      const entry = node && state.checkboxes.get(node);
      if (!entry) return null;
      const checked = entry.bubble.isChecked ? entry.bubble.isChecked() : false;
      return {type: 'buttons', text: `monitor checkbox ${blockLabel(entry.block, true)} (${checked ? 'checked' : 'unchecked'})`,
        root: node, area: env.flyoutArea, flyout: true};
    }
    if (classes.contains('blocklyMainBackground')) {
      const group = el.closest('.blocklyWorkspace');
      if (!group || group.id !== state.ws.id || !env.workspaceArea) return null;
      // Its own rect spans the toolbox and flyout too; the code area is what is left of it.
      const area = env.workspaceArea;
      return {type: 'canvas', text: 'workspace', root: el.ownerSVGElement || el, rect: area, area: area};
    }
    if (classes.contains('blocklyZoom')) {
      const kind = classes.contains('blocklyZoomIn') ? 'zoom in' : classes.contains('blocklyZoomOut') ? 'zoom out'
        : classes.contains('blocklyZoomReset') ? 'zoom reset' : 'zoom';
      return {type: 'buttons', text: kind};
    }
    return null;
  }

  function classifyHtml(el, env) {
    const tag = el.tagName.toLowerCase();
    const role = el.getAttribute('role');
    if (el.matches(DROPDOWN_ITEMS)) return {type: 'dropdown_items', text: label(el, true)};
    if (el.classList.contains('blocklyToolboxCategory') || el.classList.contains('scratchCategoryMenuItem')) {
      const name = el.querySelector('.blocklyToolboxCategoryLabel, .scratchCategoryMenuItemLabel');
      return {type: 'category_menu_item', text: clean(name ? name.textContent : el.textContent)};
    }
    if (tag === 'canvas') return el === env.stageCanvas ? {type: 'stage', text: 'stage'} : null;
    if (tag === 'input' && (el.type === 'radio' || el.type === 'checkbox')) {
      // People click the label; hit-test it as a whole.
      const labelEl = el.labels && el.labels[0];
      return {type: 'buttons', text: describeChoice(el), root: labelEl || el};
    }
    if (tag === 'input' || tag === 'textarea') {
      if (tag === 'input' && (el.type === 'hidden' || el.type === 'file')) return null;
      return {type: 'inputs', text: describeInput(el)};
    }
    if (role === 'tab') return {type: 'tabs', text: label(el)};
    if (el.matches(MENU_BAR_ITEM)) {
      // A wrapper around the title field or a button is not itself a target (an open menu's
      // buttons sit inside its menu-bar button, which stays one).
      if (tag !== 'button' && el.querySelector('input, button')) return null;
      return {type: 'menu', text: label(el), needsText: true};
    }
    if (el.matches('[class*="green-flag_green-flag"]')) return {type: 'green_flag', text: label(el) || 'green flag'};
    if (el.matches('[class*="stop-all_stop-all"]')) return {type: 'stop', text: label(el) || 'stop'};
    if (el.matches(SPRITE_TILE)) {
      const name = el.querySelector('[class*="sprite-selector-item_sprite-name"]');
      const tile = el.querySelector('[role="button"]');
      return {type: 'sprites', text: clean(name ? name.textContent : (tile && tile.getAttribute('aria-label')) || el.textContent)};
    }
    if (el.matches(STAGE_SELECTOR)) {
      // The selector is a tall column; its tile is what is drawn above the add-backdrop menu.
      const parts = Array.from(el.children).filter((c) => !c.matches('[class*="action-menu"]')).map((c) => c.getBoundingClientRect());
      const header = el.querySelector('[class*="stage-selector_header-title"]');
      return {type: 'stage_selector', text: clean(header ? header.textContent : '') || 'Stage', rect: rects.union(parts)};
    }
    if (tag === 'button' || role === 'button') {
      if (tag === 'button' && el.closest(MENU_BAR_ITEM)) return {type: 'menu', text: label(el)};
      if (el.closest(STAGE_HEADER)) return {type: 'stage_buttons', text: label(el)};
      return {type: 'buttons', text: label(el)};
    }
    return null;
  }

  function absorbed(el, claimed) {
    for (let node = el.parentNode; node && node !== document; node = node.parentNode) {
      const type = claimed.get(node);
      if (type === undefined) continue;
      const policy = ABSORB[type] || 'all';
      if (policy === 'none') return false;
      if (policy === 'buttons' && el.tagName.toLowerCase() === 'button') return false;
      if (policy === 'menus' && el.matches(DROPDOWN_ITEMS)) return false;
      return true;
    }
    return false;
  }

  function collectElements(env) {
    const claimed = new Map();
    const elements = [];
    const flyoutSlots = [];
    for (const el of document.querySelectorAll(CANDIDATES)) {
      if (claimed.size && absorbed(el, claimed)) continue;
      const item = classify(el, env);
      if (!item) continue;
      claimed.set(el, item.type);
      const root = item.root || el;
      const rect = item.rect || el.getBoundingClientRect();
      if (!rect || !(rect.width > 0) || !(rect.height > 0)) continue;
      const area = item.area === undefined ? env.viewport : item.area;
      const clipped = area && rects.intersection(rect, area);
      if (!clipped) continue;
      let visible = rects.centreHits(root, clipped);
      if (!visible && item.block) {
        // A C block's centre can lie in its empty mouth: its top arm still shows.
        const middle = rects.centre(clipped);
        visible = rects.hits(root, Math.min(clipped.x + 12, middle.x), Math.min(clipped.y + 12, middle.y));
      }
      if (!visible) continue;
      if (item.needsText && !item.text) continue;
      const entry = Object.assign({type: item.type, text: item.text || ''}, rects.rounded(clipped), item.extra || {});
      if (item.flyout) flyoutSlots.push(elements.length);
      if (item.block && !item.flyout) env.visibleBlocks.add(el);
      elements.push(entry);
    }
    // Blockly keeps the flyout's DOM in render order; list its contents top to bottom instead.
    const ordered = flyoutSlots.map((i) => elements[i]).sort((a, b) => (a.y - b.y) || (a.x - b.x));
    flyoutSlots.forEach((slot, i) => { elements[slot] = ordered[i]; });
    return elements;
  }

  // The text of the canvas blocks listed as visible, clipped to the code area. (Their own hit
  // tests vouch for them; one per text would double the cost of the pass.)
  function collectTextBoxes(env) {
    const state = env.blockly;
    const area = env.workspaceArea;
    if (!state || !area || !env.visibleBlocks.size) return [];
    const canvas = state.ws.getCanvas ? state.ws.getCanvas() : null;
    if (!canvas) return [];
    const boxes = [];
    for (const node of canvas.querySelectorAll('.blocklyBlock text')) {
      if (!env.visibleBlocks.has(node.closest('.blocklyDraggable'))) continue;
      const text = clean(node.textContent);
      if (!text) continue;
      const clipped = rects.intersection(node.getBoundingClientRect(), area);
      if (!clipped) continue;
      boxes.push(Object.assign({text: text}, rects.rounded(clipped)));
    }
    // Reading order (rows of ~10 px): Blockly nests a block's text after the blocks inside it.
    const row = (t) => Math.round((t.y + t.height / 2) / 10);
    return boxes.sort((a, b) => (row(a) - row(b)) || (a.x - b.x));
  }

  function isIcon(img) {
    if (img.closest('[class*="menu-bar_menu-bar"]')) return true;
    const owner = img.closest('button, [role="button"]');
    if (!owner) return false;
    const rect = owner.getBoundingClientRect();
    return owner.tagName === 'BUTTON' || (rect.width <= MAX_ICON_BUTTON && rect.height <= MAX_ICON_BUTTON);
  }

  function collectPixelRegions(env) {
    const regions = [];
    for (const el of document.querySelectorAll('canvas, img')) {
      const isImage = el.tagName.toLowerCase() === 'img';
      const rect = el.getBoundingClientRect();
      if (isImage && (rect.width <= MIN_IMAGE_SIDE || rect.height <= MIN_IMAGE_SIDE)) continue;
      // Icons of buttons and of the menu bar carry no text an agent needs read; pictures in
      // tiles (sprites, costumes) may.
      if (isImage && isIcon(el)) continue;
      const clipped = rects.intersection(rect, env.viewport);
      if (!clipped) continue;
      const middle = rects.centre(clipped);
      const hit = document.elementFromPoint(middle.x, middle.y);
      if (!hit || !(hit === el || el.contains(hit) || hit.contains(el))) continue;
      const kind = el === env.stageCanvas ? 'stage' : isImage ? 'image' : 'canvas';
      regions.push(Object.assign(rects.rounded(clipped), {kind: kind}));
    }
    return regions;
  }

  function stageCanvas() {
    try {
      const renderer = ctx.requireVm().renderer;
      return renderer ? renderer.canvas || (renderer.gl && renderer.gl.canvas) || null : null;
    } catch (e) {
      return null;
    }
  }

  function primitiveElements() {
    const started = ctx.realNow();
    const state = blocklyState();
    settle.watch(state);
    const viewport = rects.viewport();
    const env = {
      viewport: viewport,
      blockly: state,
      workspaceArea: state && state.view ? rects.intersection(state.view, viewport) : null,
      flyoutArea: state && state.flyoutSvg ? rects.intersection(state.flyoutSvg.getBoundingClientRect(), viewport) : null,
      stageCanvas: stageCanvas(),
      visibleBlocks: new Set(),
    };
    const elements = collectElements(env);
    const textBoxes = collectTextBoxes(env);
    const pixelRegions = collectPixelRegions(env);
    return {elements: elements, textBoxes: textBoxes, pixelRegions: pixelRegions, elapsedMs: ctx.realNow() - started};
  }

  return {api: {primitiveElements: primitiveElements}};
}});
