/*
 * What opens over the workspace: a field's dropdown or a context menu, the text editor of a
 * field, the colour picker of a colour field, and the GUI's modal dialogs (new variable, new list, ...), with their items and inputs
 * in page pixels. Read-only.
 */
scratchworldModule({name: 'geometry/widgets', requires: ['rects'], create(ctx, rects) {
  'use strict';

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
      const rect = rects.rectOf(element);
      const c = rects.centre(rect);
      const hit = document.elementFromPoint(c.x, c.y);
      const content = element.querySelector('.blocklyMenuItemContent') || element;
      return {text: content.textContent.trim(), rect: rect, visible: !!hit && hit.closest('.blocklyMenuItem') === element};
    });
    return {open: true, items: items, rect: rects.rectOf(box)};
  }

  function textEditor() {
    const input = document.querySelector('.blocklyWidgetDiv .blocklyHtmlInput');
    const open = shown(input);
    return {open: open, focused: !!input && document.activeElement === input, value: input ? input.value : null,
            rect: open ? rects.rectOf(input) : null};
  }

  function modal() {
    const content = document.querySelector('.ReactModal__Content');
    if (!shown(content)) return {open: false};
    const title = content.querySelector('[class*="modal_header-item-title"]');
    return {
      open: true,
      title: title ? title.textContent.trim() : '',
      inputs: [...content.querySelectorAll('input[type="text"], input:not([type])')].filter(shown).map((input) => ({
        rect: rects.rectOf(input), value: input.value, focused: document.activeElement === input
      })),
      options: [...content.querySelectorAll('label')].filter((label) => label.querySelector('input[type="radio"]') && shown(label)).map((label) => ({
        text: label.textContent.trim(), rect: rects.rectOf(label), checked: label.querySelector('input[type="radio"]').checked
      })),
      buttons: [...content.querySelectorAll('button')].filter(shown).map((button) => ({text: button.textContent.trim(), rect: rects.rectOf(button)}))
    };
  }

  // The open colour picker of a colour field: its hue, saturation and brightness sliders (range
  // inputs), in that order, with their values and bounds as the inputs hold them, and its eyedropper.
  function colourPicker() {
    const picker = document.querySelector('.blocklyDropDownDiv .scratchColourPicker');
    if (!shown(picker)) return {open: false, sliders: [], eyedropper: null};
    const sliders = [...picker.querySelectorAll('input[type="range"]')].map((input) => ({
      rect: rects.rectOf(input),
      value: Number(input.value),
      min: Number(input.min),
      max: Number(input.max),
      step: Number(input.step) || 1,
      focused: document.activeElement === input
    }));
    const eyedropper = picker.querySelector('.scratchEyedropper');
    return {open: true, sliders: sliders, eyedropper: eyedropper && shown(eyedropper) ? rects.rectOf(eyedropper) : null};
  }

  return {
    menu: menu, textEditor: textEditor, modal: modal, colourPicker: colourPicker,
    api: {
      geometryMenu: () => menu(), geometryTextEditor: () => textEditor(), geometryModal: () => modal(),
      geometryColourPicker: () => colourPicker(),
    },
  };
}});
