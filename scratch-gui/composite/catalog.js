/*
 * The block catalog of composite mode, exactly the editor's: shapes (inputs, fields, hat,
 * reporter, boolean) from the editor's own Blockly definitions, built on a headless workspace;
 * creation templates from the toolbox, per target (its costumes, sounds and backdrops are the
 * defaults); dropdown choices from the fields themselves. `compositeCatalog` lists it for an
 * agent's system prompt.
 */
scratchworldModule({name: 'composite/catalog', requires: ['blockly', 'composite/arguments', 'composite/target'], create(ctx, blockly, checks, editing) {
  'use strict';

  const CATEGORY_PREFIXES = ['motion_', 'looks_', 'sound_', 'event_', 'control_', 'sensing_', 'operator_', 'data_'];
  const NUMERIC_SHADOWS = ['math_number', 'math_positive_number', 'math_whole_number', 'math_integer', 'math_angle'];

  // Blocks of the Variables category are drawn by Blockly at run time, not listed in the toolbox.
  const TEMPLATES = {
    data_variable: '<block type="data_variable"><field name="VARIABLE"></field></block>',
    data_setvariableto: '<block type="data_setvariableto"><field name="VARIABLE"></field><value name="VALUE"><shadow type="text"><field name="TEXT">0</field></shadow></value></block>',
    data_changevariableby: '<block type="data_changevariableby"><field name="VARIABLE"></field><value name="VALUE"><shadow type="math_number"><field name="NUM">1</field></shadow></value></block>',
    data_showvariable: '<block type="data_showvariable"><field name="VARIABLE"></field></block>',
    data_hidevariable: '<block type="data_hidevariable"><field name="VARIABLE"></field></block>',
    data_listcontents: '<block type="data_listcontents"><field name="LIST"></field></block>',
    data_addtolist: '<block type="data_addtolist"><value name="ITEM"><shadow type="text"><field name="TEXT">thing</field></shadow></value><field name="LIST"></field></block>',
    data_deleteoflist: '<block type="data_deleteoflist"><value name="INDEX"><shadow type="math_integer"><field name="NUM">1</field></shadow></value><field name="LIST"></field></block>',
    data_deletealloflist: '<block type="data_deletealloflist"><field name="LIST"></field></block>',
    data_insertatlist: '<block type="data_insertatlist"><value name="ITEM"><shadow type="text"><field name="TEXT">thing</field></shadow></value><value name="INDEX"><shadow type="math_integer"><field name="NUM">1</field></shadow></value><field name="LIST"></field></block>',
    data_replaceitemoflist: '<block type="data_replaceitemoflist"><value name="INDEX"><shadow type="math_integer"><field name="NUM">1</field></shadow></value><field name="LIST"></field><value name="ITEM"><shadow type="text"><field name="TEXT">thing</field></shadow></value></block>',
    data_itemoflist: '<block type="data_itemoflist"><value name="INDEX"><shadow type="math_integer"><field name="NUM">1</field></shadow></value><field name="LIST"></field></block>',
    data_itemnumoflist: '<block type="data_itemnumoflist"><value name="ITEM"><shadow type="text"><field name="TEXT">thing</field></shadow></value><field name="LIST"></field></block>',
    data_lengthoflist: '<block type="data_lengthoflist"><field name="LIST"></field></block>',
    data_listcontainsitem: '<block type="data_listcontainsitem"><field name="LIST"></field><value name="ITEM"><shadow type="text"><field name="TEXT">thing</field></shadow></value></block>',
    data_showlist: '<block type="data_showlist"><field name="LIST"></field></block>',
    data_hidelist: '<block type="data_hidelist"><field name="LIST"></field></block>',
    // Message menus are filled by Blockly on render, so the toolbox leaves them out.
    event_whenbroadcastreceived: '<block type="event_whenbroadcastreceived"><field name="BROADCAST_OPTION" variabletype="broadcast_msg"></field></block>',
    event_broadcast: '<block type="event_broadcast"><value name="BROADCAST_INPUT"><shadow type="event_broadcast_menu"><field name="BROADCAST_OPTION" variabletype="broadcast_msg"></field></shadow></value></block>',
    event_broadcastandwait: '<block type="event_broadcastandwait"><value name="BROADCAST_INPUT"><shadow type="event_broadcast_menu"><field name="BROADCAST_OPTION" variabletype="broadcast_msg"></field></shadow></value></block>'
  };

  // Blockly cannot build blocks with variable or message fields without a rendered workspace, so
  // their shapes are stated here.
  const statement = (inputs, field) => ({previous: true, next: true, reporter: false, boolean: false, hat: false,
    inputs: inputs.map((name) => ({name: name, kind: 'value', boolean: false})), fields: [field]});
  const reporter = (inputs, field, isBoolean) => Object.assign(statement(inputs, field),
    {previous: false, next: false, reporter: true, boolean: !!isBoolean});
  const FIXED_SHAPES = {
    data_variable: reporter([], 'VARIABLE'),
    data_setvariableto: statement(['VALUE'], 'VARIABLE'),
    data_changevariableby: statement(['VALUE'], 'VARIABLE'),
    data_showvariable: statement([], 'VARIABLE'),
    data_hidevariable: statement([], 'VARIABLE'),
    data_listcontents: reporter([], 'LIST'),
    data_addtolist: statement(['ITEM'], 'LIST'),
    data_deleteoflist: statement(['INDEX'], 'LIST'),
    data_deletealloflist: statement([], 'LIST'),
    data_insertatlist: statement(['ITEM', 'INDEX'], 'LIST'),
    data_replaceitemoflist: statement(['INDEX', 'ITEM'], 'LIST'),
    data_itemoflist: reporter(['INDEX'], 'LIST'),
    data_itemnumoflist: reporter(['ITEM'], 'LIST'),
    data_lengthoflist: reporter([], 'LIST'),
    data_listcontainsitem: reporter(['ITEM'], 'LIST', true),
    data_showlist: statement([], 'LIST'),
    data_hidelist: statement([], 'LIST'),
    event_whenbroadcastreceived: Object.assign(statement([], 'BROADCAST_OPTION'), {previous: false, hat: true}),
    event_broadcast: Object.assign(statement(['BROADCAST_INPUT'], null), {fields: []}),
    event_broadcastandwait: Object.assign(statement(['BROADCAST_INPUT'], null), {fields: []})
  };

  let headless = null;
  const shapeCache = new Map();
  const templateCache = new Map();

  function headlessBlock(opcode) {
    const SB = blockly.scratchBlocks();
    if (!headless) headless = new SB.Workspace();
    if (!SB.Blocks[opcode]) return null;
    try {
      return headless.newBlock(opcode);
    } catch (e) {
      return null;
    }
  }

  /* ---------- the catalog: shapes from Blockly, templates from the toolbox ---------- */

  function inCatalog(opcode) {
    return CATEGORY_PREFIXES.some((p) => opcode.startsWith(p)) && !opcode.endsWith('_menu') && opcode !== 'data_listindexall';
  }

  // {hat, cap, reporter, boolean, previous, next, inputs: [{name, kind: value|statement, boolean}], fields: [names]}
  function shapeOf(opcode) {
    if (Object.prototype.hasOwnProperty.call(FIXED_SHAPES, opcode)) return FIXED_SHAPES[opcode];
    if (shapeCache.has(opcode)) return shapeCache.get(opcode);
    const block = headlessBlock(opcode);
    let shape = null;
    if (block) {
      const output = block.outputConnection;
      const outputCheck = output && output.getCheck ? output.getCheck() : null;
      const inputs = [];
      const fields = [];
      for (const input of block.inputList) {
        for (const field of input.fieldRow) if (field.name) fields.push(field.name);
        if (!input.name || !input.connection) continue;
        const check = input.connection.getCheck ? input.connection.getCheck() : null;
        inputs.push({
          name: input.name,
          kind: input.type === 3 ? 'statement' : 'value',
          boolean: !!(check && check.length === 1 && check[0] === 'Boolean')
        });
      }
      shape = {
        previous: !!block.previousConnection,
        next: !!block.nextConnection,
        reporter: !!output,
        boolean: !!(outputCheck && outputCheck.indexOf('Boolean') !== -1 && outputCheck.length === 1),
        inputs: inputs,
        fields: fields
      };
      shape.hat = !shape.previous && !shape.reporter;
      block.dispose(false);
    }
    shapeCache.set(opcode, shape);
    return shape;
  }

  // Per target: the toolbox's defaults name the target's own costumes, sounds and backdrops.
  function toolboxTemplates(target) {
    const key = target.id;
    if (templateCache.has(key)) return templateCache.get(key);
    const xml = ctx.blocksComponent().getToolboxXML();
    const dom = new DOMParser().parseFromString(xml, 'text/xml');
    const templates = new Map();
    for (const element of dom.getElementsByTagName('block')) {
      const type = element.getAttribute('type');
      if (type && !templates.has(type) && element.parentElement && element.parentElement.tagName === 'category') {
        templates.set(type, element);
      }
    }
    templateCache.set(key, templates);
    return templates;
  }

  function catalogFor(target) {
    const names = new Set([...toolboxTemplates(target).keys()].filter(inCatalog));
    for (const opcode of Object.keys(TEMPLATES)) names.add(opcode);
    return names;
  }

  function choicesOf(opcode, fieldName, target) {
    if (fieldName === 'VARIABLE') return editing.variablesInScope(target, '').map((e) => e.variable.name);
    if (fieldName === 'LIST') return editing.variablesInScope(target, 'list').map((e) => e.variable.name);
    if (fieldName === 'BROADCAST_OPTION' || fieldName === 'BROADCAST_INPUT') return editing.variablesInScope(target, 'broadcast_msg').map((e) => e.variable.name);
    const block = headlessBlock(opcode);
    if (!block) return null;
    try {
      const field = block.getField(fieldName);
      if (!field || typeof field.getOptions !== 'function') return null;
      return field.getOptions().map((option) => (typeof option[0] === 'string' ? option[0] : option[1]));
    } catch (e) {
      return null;
    } finally {
      block.dispose(false);
    }
  }

  // Toolbox entries omit what Blockly fills in on creation (dropdown defaults); a headless
  // round trip through Blockly yields the block exactly as the editor would create it.
  function completeTemplate(template) {
    const SB = blockly.scratchBlocks();
    if (!headless) headless = new SB.Workspace();
    const element = template.cloneNode(true);
    stripWhitespace(element);
    let block;
    try {
      block = SB.Xml.domToBlock(element, headless);
    } catch (e) {
      return element; // blocks with message fields need a rendered workspace; their entry is complete
    }
    try {
      return SB.Xml.blockToDom(block);
    } finally {
      block.dispose(false);
    }
  }

  function stripWhitespace(node) {
    for (const child of [...node.childNodes]) {
      if (child.nodeType === 3 && !child.nodeValue.trim()) node.removeChild(child);
      else if (child.nodeType === 1) stripWhitespace(child);
    }
  }

  function matchChoice(opcode, fieldName, value, target) {
    const block = headlessBlock(opcode);
    if (!block) return null;
    try {
      const field = block.getField(fieldName);
      if (!field || typeof field.getOptions !== 'function') return {free: true};
      const options = field.getOptions().map((o) => ({text: typeof o[0] === 'string' ? o[0] : String(o[1]), value: String(o[1])}));
      const hit = options.find((o) => o.value === value) || options.find((o) => o.text === value) ||
        options.find((o) => o.text.toLowerCase() === value.toLowerCase());
      if (!hit) {
        throw new checks.ActionError('INVALID_ARG', `${checks.quote(value)} is not a choice of ${fieldName}; choices: ${options.map((o) => checks.quote(o.text)).join(', ')}`,
          {choices: options.map((o) => o.text)});
      }
      return {value: hit.value};
    } finally {
      block.dispose(false);
    }
  }

  // Every block add_block can create for the editing target, with its shape, inputs and fields:
  // the block catalog of an agent's system prompt, read from the editor's own definitions.
  function catalog() {
    const target = editing.target();
    const blocks = [];
    for (const opcode of [...catalogFor(target)].sort()) {
      const shape = shapeOf(opcode);
      if (!shape) continue;
      const statements = shape.inputs.filter((input) => input.kind === 'statement');
      const kind = shape.hat ? 'hat' : shape.boolean ? 'boolean' : shape.reporter ? 'reporter'
        : statements.length ? 'c' : shape.next ? 'stack' : 'cap';
      blocks.push({
        opcode: opcode,
        shape: kind,
        inputs: shape.inputs.map((input) => ({name: input.name, kind: input.kind === 'statement' ? 'statement' : input.boolean ? 'boolean' : 'value'})),
        fields: shape.fields.filter(Boolean).map((name) => ({name: name, choices: choicesOf(opcode, name, target)}))
      });
    }
    return {target: target.getName(), blocks: blocks};
  }

  return {
    TEMPLATES: TEMPLATES, NUMERIC_SHADOWS: NUMERIC_SHADOWS, inCatalog: inCatalog, shapeOf: shapeOf,
    toolboxTemplates: toolboxTemplates, catalogFor: catalogFor, choicesOf: choicesOf, matchChoice: matchChoice,
    completeTemplate: completeTemplate, stripWhitespace: stripWhitespace,
    api: {compositeCatalog: () => catalog()},
  };
}});
