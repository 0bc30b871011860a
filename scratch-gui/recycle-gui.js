/*
 * Reusing an agent's editor page: the editor's own UI state, put back as a fresh page has it.
 *
 * recycle.js undoes what code left in the page; an agent also leaves the *editor* changed: a menu,
 * a dropdown or a library open, the costumes tab shown, the small stage, a half-done drag, a text
 * field being edited, the palette scrolled to another category, the workspace zoomed (the GUI
 * gives the next project's sprites the workspace's current zoom and scroll), a panel scrolled,
 * "restore sprite" on offer. Loading the next project resets the workspace's blocks, variables,
 * monitors and the selected sprite; the rest is reset here, and then compared with the fresh page:
 * the GUI store's UI slices, Blockly's overlays, gestures, zoom and scroll, the palette's category
 * and scroll, scrolled elements and the focused element. Any difference is reported, and the page
 * is closed instead of reused.
 */
(function () {
  'use strict';

  // Store slices that describe the UI rather than the project (compared as JSON, with the fields
  // that hold functions or project data left out).
  const UI_SLICES = [
    'alerts', 'assetDrag', 'blockDrag', 'colorPicker', 'connectionModal', 'customProcedures', 'editorTab',
    'mode', 'hoveredTarget', 'stageSize', 'menus', 'micIndicator', 'modals', 'projectChanged', 'projectTitle',
    'settings', 'timeTravel',
  ];
  const DROPPED_FIELDS = new Set(['callback', 'restoreFun', 'img', 'content', 'mutator']);
  const FRAMES_FOR_REACT = 2;

  let clean = null;
  let cleanPaletteOffset = 0; // the fresh palette's scroll, exactly, as its scrollbar takes it
  let cleanView = null; // the fresh workspace's scroll and zoom, exactly

  function uiState(gui) {
    const state = gui.store.getState();
    const slices = {};
    for (const name of UI_SLICES) slices[name] = state.scratchGui[name];
    slices.cards = {visible: state.scratchGui.cards.visible, activeDeckId: state.scratchGui.cards.activeDeckId};
    slices.restoreDeletion = {deletedItem: state.scratchGui.restoreDeletion.deletedItem,
      offered: !!state.scratchGui.restoreDeletion.restoreFun};
    slices.locale = state.locales.locale;
    return JSON.parse(JSON.stringify(slices, (key, value) => (DROPPED_FIELDS.has(key) ? undefined : value)));
  }

  function blocklyState(gui) {
    const component = gui.blocks();
    const SB = component.ScratchBlocks;
    const ws = component.workspace;
    const flyout = ws.getFlyout();
    const toolbox = ws.getToolbox();
    const selected = toolbox && toolbox.getSelectedItem();
    return {
      widgetOpen: !!(SB.WidgetDiv && SB.WidgetDiv.isVisible()),
      dropDownOpen: !!(SB.DropDownDiv && SB.DropDownDiv.isVisible()),
      gesture: !!ws.currentGesture_ || !!(flyout && flyout.getWorkspace().currentGesture_),
      dragging: !!(ws.isDragging && ws.isDragging()),
      category: selected ? selected.getId() : null,
      zoom: [ws.scrollX, ws.scrollY, ws.scale].map((value) => Math.round(value * 1000) / 1000),
      paletteScroll: flyout ? Math.round(flyout.getWorkspace().scrollY) : null,
    };
  }

  // Elements scrolled away from their origin (the GUI's panels keep their content in view).
  function scrolledElements() {
    return [...document.querySelectorAll('*')].filter((el) => el.scrollTop !== 0 || el.scrollLeft !== 0);
  }

  function unscroll() {
    for (const el of scrolledElements()) el.scrollTo(0, 0);
  }

  const describeElement = (el) => `${el.tagName.toLowerCase()}.${String(el.className && el.className.baseVal !== undefined ? el.className.baseVal : el.className).split(' ')[0]}`;

  function pageState() {
    const focused = document.activeElement;
    return {
      focused: focused ? focused.tagName : null,
      fullscreen: !!document.fullscreenElement,
      scrolled: scrolledElements().map((el) => `${describeElement(el)} ${el.scrollLeft},${el.scrollTop}`),
    };
  }

  function snapshot(gui) {
    return {ui: uiState(gui), blockly: blocklyState(gui), page: pageState()};
  }

  /** Record the fresh page's UI, once it is ready. */
  function markClean(gui) {
    clean = snapshot(gui);
    const ws = gui.blocks().workspace;
    cleanPaletteOffset = -ws.getFlyout().getWorkspace().scrollY;
    cleanView = {scrollX: ws.scrollX, scrollY: ws.scrollY, scale: ws.scale};
  }

  const nextFrame = () => new Promise((resolve) => requestAnimationFrame(() => resolve()));

  function resetBlockly(gui, differences) {
    const component = gui.blocks();
    const SB = component.ScratchBlocks;
    const ws = component.workspace;
    try {
      const flyout = ws.getFlyout();
      for (const workspace of [ws, flyout.getWorkspace()]) {
        if (workspace.currentGesture_) workspace.currentGesture_.cancel();
      }
      SB.hideChaff();
      SB.WidgetDiv.hide();
      SB.DropDownDiv.hideWithoutAnimation();
      const toolbox = ws.getToolbox();
      const selected = toolbox.getSelectedItem();
      if (!selected || selected.getId() !== clean.blockly.category) {
        toolbox.setSelectedItem(toolbox.getToolboxItemById(clean.blockly.category));
      }
      flyout.scrollTarget = undefined; // no scroll animation left running
      flyout.getWorkspace().scrollbar.setY(cleanPaletteOffset);
      // The agent's blocks go from the screen (not from the VM: no events), as in the fresh page
      // whose sprite had none; left there, they would bound the scroll the view is put back to.
      SB.Events.disable();
      try {
        ws.clear();
      } finally {
        SB.Events.enable();
      }
      ws.setScale(cleanView.scale); // draws the grid at that scale too
      Object.assign(ws, cleanView); // as the GUI itself sets a sprite's saved view
      ws.resize();
    } catch (e) {
      differences.push(`the block editor cannot be reset: ${e && e.message}`);
    }
  }

  /**
   * Show the loaded project's sprite position in the palette's motion blocks, as a fresh page does.
   * The GUI writes it there on the VM's next targets update, which on the real clock may come after
   * an agent's first look; until then a recycled page would show where the last project's sprite was
   * (a fresh page draws a new palette, from XML holding 0s, for its first project). Not through the
   * GUI's own handler (`onTargetsUpdate`): it queues the write behind the toolbox refresh that the
   * load started, and the first screenshot still showed the last project's position.
   */
  function showTargetPosition(gui) {
    const component = gui.blocks();
    const target = component.props.vm.editingTarget;
    if (!target) return;
    const palette = component.workspace.getFlyout().getWorkspace();
    for (const prefix of ['glide', 'move', 'set']) {
      for (const axis of ['x', 'y']) {
        const block = palette.getBlockById(prefix + axis); // the ids the GUI gives these fields' blocks
        if (block) block.inputList[0].fieldRow[0].setValue(String(Math.round(target[axis])));
      }
    }
  }

  // Every UI slice that an agent can change and an action can undo goes back to its fresh value.
  function resetStore(gui) {
    const store = gui.store;
    const ui = () => store.getState().scratchGui;
    const dispatch = (action) => store.dispatch(action);
    for (const [menu, open] of Object.entries(ui().menus)) {
      if (open) dispatch({type: 'scratch-gui/menus/CLOSE_MENU', menu: menu});
    }
    for (const [modal, open] of Object.entries(ui().modals)) {
      if (open) dispatch({type: 'scratch-gui/modals/CLOSE_MODAL', modal: modal});
    }
    for (let i = ui().alerts.alertsList.length; i > 0; i--) dispatch({type: 'scratch-gui/alerts/CLOSE_ALERT', index: 0});
    if (ui().cards.visible) dispatch({type: 'scratch-gui/cards/CLOSE_CARDS'});
    if (ui().colorPicker.active) dispatch({type: 'scratch-gui/color-picker/DEACTIVATE_COLOR_PICKER', color: null});
    if (ui().customProcedures.active) {
      dispatch({type: 'scratch-gui/custom-procedures/DEACTIVATE_CUSTOM_PROCEDURES', mutator: null});
    }
    dispatch({type: 'scratch-gui/navigation/ACTIVATE_TAB', activeTabIndex: clean.ui.editorTab.activeTabIndex});
    dispatch({type: 'scratch-gui/StageSize/SET_STAGE_SIZE', stageSize: clean.ui.stageSize.stageSize});
    dispatch({type: 'scratch-gui/hovered-target/SET_HOVERED_SPRITE', spriteId: null});
    dispatch({type: 'scratch-gui/restore-deletion/RESTORE_UPDATE', state: {restoreFun: null, deletedItem: ''}});
    dispatch({type: 'scratch-gui/project-changed/SET_PROJECT_CHANGED', changed: clean.ui.projectChanged});
    dispatch({type: 'scratch-gui/block-drag/BLOCK_DRAG_UPDATE', areBlocksOverGui: clean.ui.blockDrag});
    dispatch({type: 'scratch-gui/mode/SET_FULL_SCREEN', isFullScreen: clean.ui.mode.isFullScreen});
    dispatch({type: 'scratch-gui/mode/SET_PLAYER', isPlayerOnly: clean.ui.mode.isPlayerOnly});
  }

  /**
   * Put the editor's UI back as the fresh page had it; resolves (after React has rendered the
   * change) to what could not be reset.
   */
  async function reset(gui) {
    if (!clean) return ['the page was not marked clean'];
    const differences = [];
    if (document.activeElement && document.activeElement !== document.body) document.activeElement.blur();
    unscroll();
    resetStore(gui);
    if (document.fullscreenElement && document.exitFullscreen) await document.exitFullscreen();
    // The block editor after the store: showing the code tab again restores the sprite's saved view.
    for (let i = 0; i < FRAMES_FOR_REACT; i++) await nextFrame();
    resetBlockly(gui, differences);
    for (let i = 0; i < FRAMES_FOR_REACT; i++) await nextFrame();
    unscroll(); // again: a panel inside a tab that was hidden keeps its scroll and shows it now
    return differences;
  }

  function differencesIn(label, now, fresh, into) {
    for (const key of new Set([...Object.keys(now), ...Object.keys(fresh)])) {
      const a = JSON.stringify(now[key]);
      const b = JSON.stringify(fresh[key]);
      if (a !== b) into.push(`${label} ${key} is ${a}, fresh ${b}`);
    }
  }

  /** What still differs from the fresh page's UI (empty: as good as fresh). */
  function compare(gui) {
    if (!clean) return ['the page was not marked clean'];
    const now = snapshot(gui);
    const differences = [];
    for (const part of ['ui', 'blockly', 'page']) differencesIn(part, now[part], clean[part], differences);
    return differences;
  }

  window.__scratchworldGuiState = Object.freeze({markClean, reset, compare, showTargetPosition});
})();
