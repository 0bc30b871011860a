/*
 * Composite mode: a text observation of the editing target and a semantic block-editing API.
 *
 * Every edit is made on the VM's own block container, synchronously, so the VM (and the project
 * saved from it) reflects an action the moment it returns; the visible workspace is redrawn
 * from the VM only when asked (`compositeSyncWorkspace`), because redrawing costs ~100 ms on a
 * real project and nothing in composite mode looks at it. Block shapes, default inputs and
 * dropdown choices come from the editor's own Blockly definitions and toolbox, so the catalog is
 * exactly the editor's.
 *
 * Agent mistakes are answers, never exceptions: `execute` returns an envelope
 * `{success, data, error: {code, message, details}}` with a stable code. Arguments are data:
 * nothing an agent sends is ever evaluated as code.
 */
(function () {
  'use strict';

  const CATEGORY_PREFIXES = ['motion_', 'looks_', 'sound_', 'event_', 'control_', 'sensing_', 'operator_', 'data_'];
  const STATEMENT_INPUTS = ['SUBSTACK', 'SUBSTACK2'];
  const NUMERIC_SHADOWS = ['math_number', 'math_positive_number', 'math_whole_number', 'math_integer', 'math_angle'];
  const PLACEMENTS = ['stack_before', 'stack_after', 'statement_into', 'value_into', 'wrap'];
  const MAX_NAME = 200;

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

  class ActionError extends Error {
    constructor(code, message, details) {
      super(message);
      this.code = code;
      this.details = details === undefined ? null : details;
    }
  }

  // Names and values are printed quoted and escaped, so no name can forge a line of the observation.
  const quote = (value) => JSON.stringify(String(value));
  const clean = (value) => String(value).replace(/[\u0000-\u001f\u2028\u2029]/g, (c) => JSON.stringify(c).slice(1, -1));

  function factory(ctx) {
    let headless = null;
    let uid = 0; // per project: a reused page names the next project's new blocks as a fresh page would
    ctx.onProjectLoaded(() => { uid = 0; });
    const shapeCache = new Map();
    const templateCache = new Map();

    /* ---------- the editor's Blockly ---------- */

    function scratchBlocks() {
      return ctx.blocksComponent().ScratchBlocks;
    }

    function headlessBlock(opcode) {
      const SB = scratchBlocks();
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

    /* ---------- VM access ---------- */

    function vm() {
      return ctx.requireVm();
    }

    function editingTarget() {
      const target = vm().editingTarget;
      if (!target) throw new ActionError('NO_TARGET', 'no target is being edited');
      return target;
    }

    function stage() {
      return vm().runtime.getTargetForStage();
    }

    function variablesInScope(target, type) {
      const found = new Map();
      for (const owner of [stage(), target]) {
        if (!owner) continue;
        for (const variable of Object.values(owner.variables)) {
          if (variable.type === type) found.set(variable.name, {variable: variable, scope: owner.isStage ? 'all' : 'sprite'});
        }
      }
      return [...found.values()].sort((a, b) => (a.variable.name < b.variable.name ? -1 : a.variable.name > b.variable.name ? 1 : 0));
    }

    function newId(prefix) {
      uid += 1;
      return `${prefix || 'sw'}${Date.now().toString(36)}${uid.toString(36)}`;
    }

    /* ---------- numbering: one deterministic pre-order, shared by observation and actions ---------- */

    function topBlocks(blocks) {
      return blocks.getScripts().slice().map((id) => blocks.getBlock(id)).filter((b) => b && !b.shadow)
        .sort((a, b) => (Number(a.y) || 0) - (Number(b.y) || 0) || (Number(a.x) || 0) - (Number(b.x) || 0) || (a.id < b.id ? -1 : 1));
    }

    function orderedInputs(block) {
      const shape = shapeOf(block.opcode);
      // Every input of the definition is listed, filled or not (an empty CONDITION is worth seeing).
      const names = shape ? shape.inputs.map((i) => i.name) : [];
      for (const name of Object.keys(block.inputs)) if (names.indexOf(name) === -1) names.push(name);
      const value = names.filter((n) => STATEMENT_INPUTS.indexOf(n) === -1 && !(shape && shape.inputs.some((i) => i.name === n && i.kind === 'statement')));
      const statement = names.filter((n) => value.indexOf(n) === -1);
      return {value, statement};
    }

    // Walks the editing target; calls visit(block, depth, index, context) for every indexed block.
    function walk(blocks, visit) {
      let counter = 0;
      function visitChain(id, depth, topLevel) {
        let first = true;
        while (id) {
          const block = blocks.getBlock(id);
          if (!block) return;
          counter += 1;
          visit(block, depth, counter, topLevel && first);
          const {value, statement} = orderedInputs(block);
          for (const name of value) {
            const input = block.inputs[name];
            if (input && input.block && input.block !== input.shadow) {
              visit.input && visit.input(block, name, depth);
              visitChain(input.block, depth + 1, false);
            } else {
              visit.literal && visit.literal(block, name, depth);
            }
          }
          for (const name of statement) {
            const input = block.inputs[name];
            visit.statement && visit.statement(block, name, depth, !!(input && input.block));
            if (input && input.block) visitChain(input.block, depth + 1, false);
          }
          first = false;
          id = block.next;
        }
      }
      const tops = topBlocks(blocks);
      tops.forEach((block, n) => {
        visitChain(block.id, 0, true);
        visit.endScript && visit.endScript(n);
      });
      return counter;
    }

    function indexMap(target) {
      const byIndex = [null];
      walk(target.blocks, (block) => { byIndex.push(block.id); });
      return byIndex;
    }

    /* ---------- observation ---------- */

    function choicesOf(opcode, fieldName, target) {
      if (fieldName === 'VARIABLE') return variablesInScope(target, '').map((e) => e.variable.name);
      if (fieldName === 'LIST') return variablesInScope(target, 'list').map((e) => e.variable.name);
      if (fieldName === 'BROADCAST_OPTION' || fieldName === 'BROADCAST_INPUT') return variablesInScope(target, 'broadcast_msg').map((e) => e.variable.name);
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

    function choicesText(opcode, fieldName, target) {
      const choices = choicesOf(opcode, fieldName, target);
      if (!choices) return '';
      const key = `${fieldName.toLowerCase().replace(/_/g, '')}Options`;
      return ` {choices: ${JSON.stringify({[key]: choices})}}`;
    }

    function literalText(shadow, target) {
      const fieldNames = Object.keys(shadow.fields);
      if (!fieldNames.length) return `(${shadow.opcode})`;
      const field = shadow.fields[fieldNames[0]];
      const value = NUMERIC_SHADOWS.indexOf(shadow.opcode) !== -1 && field.value !== '' && !isNaN(Number(field.value))
        ? clean(field.value) : quote(field.value);
      const menu = NUMERIC_SHADOWS.indexOf(shadow.opcode) === -1 && shadow.opcode !== 'text' && shadow.opcode !== 'colour_picker';
      return `${value} (${shadow.opcode})${menu ? choicesText(shadow.opcode, fieldNames[0], target) : ''}`;
    }

    function pseudocode(target) {
      const lines = [];
      const blocks = target.blocks;
      const pad = (depth) => '  '.repeat(depth);
      const visit = (block, depth, index, isTop) => {
        const shape = shapeOf(block.opcode);
        const outside = inCatalog(block.opcode) && shape ? '' : ' (not in catalog)';
        lines.push(`${pad(depth)}#${index}${isTop ? ' [top]' : ''} ${clean(block.opcode)}${outside}`);
        const fieldOrder = shape ? shape.fields.filter((f) => block.fields[f]) : [];
        for (const name of Object.keys(block.fields)) if (fieldOrder.indexOf(name) === -1) fieldOrder.push(name);
        for (const name of fieldOrder) {
          lines.push(`${pad(depth)}- field ${clean(name)}: ${quote(block.fields[name].value)}${choicesText(block.opcode, name, target)}`);
        }
      };
      visit.input = (block, name, depth) => lines.push(`${pad(depth)}- input ${clean(name)}:`);
      visit.literal = (block, name, depth) => {
        const input = block.inputs[name];
        const shadow = input && input.shadow ? blocks.getBlock(input.shadow) : null;
        lines.push(`${pad(depth)}- input ${clean(name)}: ${shadow ? literalText(shadow, target) : '(empty)'}`);
      };
      visit.statement = (block, name, depth, filled) => lines.push(`${pad(depth)}- ${clean(name)}:${filled ? '' : ' (empty)'}`);
      visit.endScript = () => lines.push('');
      const count = walk(blocks, visit);
      return {text: lines.join('\n').replace(/\n+$/, ''), count: count};
    }

    function observe() {
      const target = editingTarget();
      const section = (entries) => entries.length ? entries.join('; ') : 'None';
      const variables = variablesInScope(target, '').map((e) => `name: ${clean(e.variable.name)}, scope: ${e.scope}`);
      const lists = variablesInScope(target, 'list').map((e) => `name: ${clean(e.variable.name)}, scope: ${e.scope}`);
      const targets = vm().runtime.targets.filter((t) => t.isOriginal).map((t) => clean(t.getName()));
      const code = pseudocode(target);
      const text = [
        '## Current Editing Target', clean(target.getName()), '',
        '## Target Variables In Scope', section(variables), '',
        '## Target Lists In Scope', section(lists), '',
        '## All Available Targets', targets.join(', '), '',
        '## Blocks Pseudocode', code.text || 'None'
      ].join('\n');
      const all = vm().runtime.targets.filter((t) => t.isOriginal).map((t) => ({name: t.getName(), isStage: t.isStage}));
      return {text: text, editingTarget: target.getName(), blockCount: code.count, targets: all};
    }

    /* ---------- argument checks ---------- */

    function requireString(args, key) {
      const value = args[key];
      if (typeof value !== 'string' || !value.length) throw new ActionError('INVALID_ARG', `${key} must be a non-empty string`);
      if (value.length > MAX_NAME) throw new ActionError('INVALID_ARG', `${key} is longer than ${MAX_NAME} characters`);
      return value;
    }

    function requireIndex(args, key, byIndex) {
      const value = args[key];
      if (typeof value !== 'number' || !Number.isInteger(value)) throw new ActionError('INVALID_ARG', `${key} must be an integer block index (#n in the pseudocode)`);
      if (value < 1 || value >= byIndex.length) {
        throw new ActionError('NOT_FOUND', `there is no block #${value}; the editing target has ${byIndex.length - 1} indexed block(s)`);
      }
      return byIndex[value];
    }

    function requireScope(args) {
      const scope = args.scope === undefined ? 'sprite' : args.scope;
      if (scope !== 'sprite' && scope !== 'all') throw new ActionError('INVALID_ARG', 'scope must be "sprite" or "all"');
      return scope;
    }

    /* ---------- structure helpers on the VM's block container ---------- */

    function chainEnd(blocks, id) {
      let block = blocks.getBlock(id);
      while (block.next) block = blocks.getBlock(block.next);
      return block;
    }

    // Where a block hangs: {parent, input} (input null: the parent's next), or null when top-level.
    function attachment(blocks, block) {
      if (!block.parent) return null;
      const parent = blocks.getBlock(block.parent);
      if (parent.next === block.id) return {parent: parent.id, input: null};
      for (const name of Object.keys(parent.inputs)) if (parent.inputs[name].block === block.id) return {parent: parent.id, input: name};
      return null;
    }

    function containsBlock(blocks, rootId, wanted) {
      const stack = [rootId];
      while (stack.length) {
        const id = stack.pop();
        if (id === wanted) return true;
        const block = blocks.getBlock(id);
        if (!block) continue;
        if (block.next) stack.push(block.next);
        for (const input of Object.values(block.inputs)) if (input.block) stack.push(input.block);
      }
      return false;
    }

    function bottomY(blocks) {
      let y = 0;
      for (const top of topBlocks(blocks)) y = Math.max(y, Number(top.y) || 0);
      return y;
    }

    // Make `id` top-level. With heal, only the block leaves: its next takes its place.
    function unplug(blocks, id, heal) {
      const block = blocks.getBlock(id);
      const at = attachment(blocks, block);
      const next = heal ? block.next : null;
      if (next) blocks.moveBlock({id: next, oldParent: id, newCoordinate: {x: 0, y: 0}});
      if (at) {
        blocks.moveBlock({id: id, oldParent: at.parent, oldInput: at.input || undefined, newCoordinate: {x: 400, y: bottomY(blocks) + 120}});
        if (at.input) restoreShadow(blocks, at.parent, at.input);
      } else if (!block.topLevel) {
        blocks.moveBlock({id: id, newCoordinate: {x: 400, y: bottomY(blocks) + 120}});
      }
      if (next) {
        if (at) attach(blocks, next, at.parent, at.input);
        else blocks.moveBlock({id: next, newCoordinate: {x: Number(block.x) || 0, y: Number(block.y) || 0}});
      }
    }

    function restoreShadow(blocks, parentId, inputName) {
      const input = blocks.getBlock(parentId).inputs[inputName];
      if (input && !input.block && input.shadow) input.block = input.shadow;
    }

    // Hang a top-level block under parent (input null: as its next).
    function attach(blocks, id, parentId, inputName) {
      blocks.moveBlock({id: id, newParent: parentId, newInput: inputName || undefined});
    }

    // The (top-level) source takes the destination's place; the destination is left top-level.
    function takePlace(blocks, sourceId, destId) {
      const dest = blocks.getBlock(destId);
      const at = attachment(blocks, dest);
      if (at) {
        blocks.moveBlock({id: destId, oldParent: at.parent, oldInput: at.input || undefined, newCoordinate: {x: 0, y: 0}});
        attach(blocks, sourceId, at.parent, at.input);
      } else {
        placeTop(blocks, sourceId, Number(dest.x) || 0, Number(dest.y) || 0);
      }
    }

    function placeTop(blocks, id, x, y) {
      blocks.moveBlock({id: id, newCoordinate: {x: x, y: y}});
    }

    function changed() {
      const theVm = vm();
      theVm.runtime.emitProjectChanged();
      if (theVm.editingTarget) theVm.editingTarget.blocks.resetCache();
    }

    /* ---------- actions ---------- */

    function selectSprite(args) {
      const name = requireString(args, 'name');
      const sprites = vm().runtime.targets.filter((t) => t.isOriginal && !t.isStage);
      const match = sprites.find((t) => t.getName() === name) || sprites.find((t) => t.getName().toLowerCase() === name.toLowerCase());
      if (!match) {
        throw new ActionError('NOT_FOUND', `no sprite named ${quote(name)}; sprites: ${sprites.map((t) => quote(t.getName())).join(', ') || 'none'}`,
          {sprites: sprites.map((t) => t.getName())});
      }
      vm().setEditingTarget(match.id);
      return {editingTarget: match.getName()};
    }

    function selectStage() {
      vm().setEditingTarget(stage().id);
      return {editingTarget: stage().getName()};
    }

    function addVariable(args, type) {
      const name = requireString(args, 'name');
      const scope = requireScope(args);
      const target = editingTarget();
      if (scope === 'sprite' && target.isStage) throw new ActionError('INVALID_ARG', 'the stage has only global variables: use scope "all"');
      const existing = variablesInScope(target, type).find((e) => e.variable.name === name);
      if (existing) return {created: {name: name, id: existing.variable.id, scope: existing.scope, created: false}};
      if (scope === 'all') {
        const clash = vm().runtime.targets.find((t) => !t.isStage && Object.values(t.variables).some((v) => v.name === name && v.type === type));
        if (clash) throw new ActionError('INVALID_ARG', `sprite ${quote(clash.getName())} already has a local ${type ? 'list' : 'variable'} named ${quote(name)}`);
      }
      const owner = scope === 'all' ? stage() : target;
      const id = newId('var');
      owner.createVariable(id, name, type);
      changed();
      return {created: {name: name, id: id, scope: scope, created: true}};
    }

    function bindVariable(target, element, fieldName, type, wanted, required) {
      const fields = [...element.getElementsByTagName('field')].filter((f) => f.getAttribute('name') === fieldName);
      if (!fields.length) return null;
      const candidates = variablesInScope(target, type);
      const what = type === 'list' ? 'list' : 'variable';
      let chosen = null;
      if (wanted !== undefined) {
        if (typeof wanted !== 'string' || !wanted.length) throw new ActionError('INVALID_ARG', `creation.${what}Name must be a non-empty string`);
        chosen = candidates.find((e) => e.variable.name === wanted);
        if (!chosen) {
          throw new ActionError('NOT_FOUND', `no ${what} named ${quote(wanted)} in scope; create it with add_${what} first`,
            {available: candidates.map((e) => e.variable.name)});
        }
      } else if (required) {
        throw new ActionError('INVALID_ARG', `this block needs creation.${what}Name`, {available: candidates.map((e) => e.variable.name)});
      } else {
        chosen = candidates[0];
        if (!chosen) throw new ActionError('NOT_FOUND', `no ${what} exists yet; create one with add_${what} first`);
      }
      for (const field of fields) {
        field.setAttribute('id', chosen.variable.id);
        field.setAttribute('variabletype', type);
        field.textContent = chosen.variable.name;
      }
      return chosen.variable.name;
    }

    // Toolbox entries omit what Blockly fills in on creation (dropdown defaults); a headless
    // round trip through Blockly yields the block exactly as the editor would create it.
    function completeTemplate(template) {
      const SB = scratchBlocks();
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

    // Broadcast menus in toolbox entries name a message the project may not have yet.
    function ensureMessages(element) {
      for (const field of element.getElementsByTagName('field')) {
        if (field.getAttribute('variabletype') !== 'broadcast_msg') continue;
        const existing = variablesInScope(editingTarget(), 'broadcast_msg');
        const name = field.textContent || (existing.length ? existing[0].variable.name : 'message1');
        const message = broadcastByName(name, true);
        field.setAttribute('id', message.id);
        field.textContent = message.name;
      }
    }

    function stripWhitespace(node) {
      for (const child of [...node.childNodes]) {
        if (child.nodeType === 3 && !child.nodeValue.trim()) node.removeChild(child);
        else if (child.nodeType === 1) stripWhitespace(child);
      }
    }

    function addBlock(args) {
      const opcode = requireString(args, 'blockType');
      const creation = args.creation === undefined ? {} : args.creation;
      if (typeof creation !== 'object' || creation === null || Array.isArray(creation)) throw new ActionError('INVALID_ARG', 'creation must be an object');
      const target = editingTarget();
      const templates = toolboxTemplates(target);
      let element;
      if (Object.prototype.hasOwnProperty.call(TEMPLATES, opcode)) {
        element = new DOMParser().parseFromString(TEMPLATES[opcode], 'text/xml').documentElement;
      } else if (templates.has(opcode) && inCatalog(opcode)) {
        element = completeTemplate(templates.get(opcode));
      } else {
        if (target.isStage && inCatalog(opcode) && scratchBlocks().Blocks[opcode]) {
          throw new ActionError('UNSUPPORTED', `${opcode} is not available for the stage; select a sprite first`);
        }
        const similar = [...catalogFor(target)].filter((o) => o.includes(opcode.split('_').pop() || opcode)).slice(0, 8);
        throw new ActionError('INVALID_ARG', `unknown block type ${quote(opcode)}`, {similar: similar});
      }
      stripWhitespace(element);
      ensureMessages(element);
      const variableName = bindVariable(target, element, 'VARIABLE', '', creation.variableName, opcode === 'data_variable');
      const listName = bindVariable(target, element, 'LIST', 'list', creation.listName, opcode === 'data_listcontents');
      const blocks = target.blocks;
      const ids = [];
      for (const node of [element, ...element.querySelectorAll('block,shadow')]) {
        const id = newId('b');
        node.setAttribute('id', id);
        ids.push(id);
      }
      element.setAttribute('x', '400');
      element.setAttribute('y', String(bottomY(blocks) + 120));
      blocks.blocklyListen({type: 'create', blockId: ids[0], xml: element});
      if (!blocks.getBlock(ids[0])) throw new ActionError('INTERNAL_ERROR', `the VM did not create ${opcode}`);
      changed();
      const byIndex = indexMap(target);
      const data = {blockId: ids[0], index: byIndex.indexOf(ids[0]), opcode: opcode};
      if (variableName !== null) data.variable = variableName;
      if (listName !== null) data.list = listName;
      return data;
    }

    function connectBlocks(args) {
      const target = editingTarget();
      const blocks = target.blocks;
      const byIndex = indexMap(target);
      const sourceId = requireIndex(args, 'sourceBlockIndex', byIndex);
      const targetId = requireIndex(args, 'targetBlockIndex', byIndex);
      if (sourceId === targetId) throw new ActionError('INVALID_ARG', 'a block cannot connect to itself');
      const placement = args.placement;
      if (typeof placement !== 'object' || placement === null || PLACEMENTS.indexOf(placement.kind) === -1) {
        throw new ActionError('INVALID_ARG', `placement.kind must be one of ${PLACEMENTS.join(', ')}`);
      }
      const source = blocks.getBlock(sourceId);
      const dest = blocks.getBlock(targetId);
      const sourceShape = shapeOf(source.opcode);
      const destShape = shapeOf(dest.opcode);
      if (!sourceShape || !destShape) throw new ActionError('UNSUPPORTED', 'blocks outside the catalog cannot be connected');
      const kind = placement.kind;
      // A hat moves with its whole script; any other block moves alone (with its inputs and C-slots).
      const movesStack = sourceShape.hat;
      if (containsBlock(blocks, sourceId, targetId) && (movesStack || !isInChainOf(blocks, sourceId, targetId))) {
        throw new ActionError('INVALID_ARG', `block #${args.targetBlockIndex} is inside block #${args.sourceBlockIndex}: that would make a cycle`);
      }
      const inputName = placement.inputName;
      if (kind === 'value_into') return valueInto(blocks, source, sourceShape, dest, destShape, inputName, args);
      if (sourceShape.reporter) {
        throw new ActionError('CONNECTION_MISMATCH', `block #${args.sourceBlockIndex} (${source.opcode}) is a reporter: use placement value_into an input`);
      }
      if (kind === 'stack_before') return stackBefore(blocks, source, sourceShape, dest, destShape, args);
      if (kind === 'stack_after') return stackAfter(blocks, source, sourceShape, dest, destShape, args);
      if (kind === 'statement_into') return statementInto(blocks, source, sourceShape, dest, destShape, inputName, args);
      return wrap(blocks, source, sourceShape, dest, destShape, args);
    }

    function isInChainOf(blocks, sourceId, targetId) {
      // true when target is only reachable through source's next chain (it moves away when source is healed out)
      const source = blocks.getBlock(sourceId);
      for (const input of Object.values(source.inputs)) if (input.block && containsBlock(blocks, input.block, targetId)) return false;
      return true;
    }

    function result(source, extra) {
      changed();
      const data = {connected: true, sourceBlockId: source.id};
      return Object.assign(data, extra || {});
    }

    function stackBefore(blocks, source, sourceShape, dest, destShape, args) {
      if (!destShape.previous) {
        throw new ActionError('CONNECTION_MISMATCH', `nothing can go before block #${args.targetBlockIndex} (${dest.opcode}): it is a hat block`);
      }
      if (sourceShape.hat && attachment(blocks, dest)) {
        throw new ActionError('CONNECTION_MISMATCH', `a hat block can only go on top of a script; block #${args.targetBlockIndex} is not the first block of one`);
      }
      const tail = sourceShape.hat ? chainEnd(blocks, source.id) : source;
      const tailShape = shapeOf(tail.opcode);
      if (!tailShape || !tailShape.next) {
        throw new ActionError('CONNECTION_MISMATCH', `nothing can follow ${tail.opcode}, so it cannot go before another block`);
      }
      unplug(blocks, source.id, !sourceShape.hat);
      takePlace(blocks, source.id, dest.id);
      attach(blocks, dest.id, tail.id, null);
      return result(source);
    }

    function stackAfter(blocks, source, sourceShape, dest, destShape, args) {
      if (sourceShape.hat) throw new ActionError('CONNECTION_MISMATCH', `block #${args.sourceBlockIndex} is a hat block: it can only start a script (stack_before its first block)`);
      if (!destShape.next) throw new ActionError('CONNECTION_MISMATCH', `nothing can follow block #${args.targetBlockIndex} (${dest.opcode})`);
      unplug(blocks, source.id, true);
      const oldNext = blocks.getBlock(dest.id).next;
      let detached = null;
      if (oldNext) blocks.moveBlock({id: oldNext, oldParent: dest.id, newCoordinate: {x: 0, y: 0}});
      attach(blocks, source.id, dest.id, null);
      if (oldNext) detached = rechain(blocks, source.id, oldNext);
      return result(source, detached ? {detachedBlockId: detached} : null);
    }

    // Hang `tailId` (top-level) after the chain starting at `headId`; if the chain ends in a cap, it stays apart.
    function rechain(blocks, headId, tailId) {
      const end = chainEnd(blocks, headId);
      if (shapeOf(end.opcode) && shapeOf(end.opcode).next) {
        attach(blocks, tailId, end.id, null);
        return null;
      }
      placeTop(blocks, tailId, 400, bottomY(blocks) + 120);
      return tailId;
    }

    function statementInputs(shape) {
      return shape.inputs.filter((i) => i.kind === 'statement').map((i) => i.name);
    }

    function valueInputs(shape) {
      return shape.inputs.filter((i) => i.kind === 'value').map((i) => i.name);
    }

    function statementInto(blocks, source, sourceShape, dest, destShape, inputName, args) {
      const names = statementInputs(destShape);
      if (typeof inputName !== 'string' || names.indexOf(inputName) === -1) {
        throw new ActionError('INPUT_NOT_FOUND', names.length
          ? `block #${args.targetBlockIndex} (${dest.opcode}) has statement inputs ${names.join(', ')}; give one as placement.inputName`
          : `block #${args.targetBlockIndex} (${dest.opcode}) has no statement input (it is not a C block)`, {statementInputs: names});
      }
      if (sourceShape.hat) throw new ActionError('CONNECTION_MISMATCH', `block #${args.sourceBlockIndex} is a hat block and cannot go inside a C block`);
      unplug(blocks, source.id, true);
      const input = blocks.getBlock(dest.id).inputs[inputName];
      const old = input && input.block ? input.block : null;
      if (old) blocks.moveBlock({id: old, oldParent: dest.id, oldInput: inputName, newCoordinate: {x: 0, y: 0}});
      attach(blocks, source.id, dest.id, inputName);
      const detached = old ? rechain(blocks, source.id, old) : null;
      return result(source, detached ? {detachedBlockId: detached} : null);
    }

    function valueInto(blocks, source, sourceShape, dest, destShape, inputName, args) {
      const names = valueInputs(destShape);
      if (typeof inputName !== 'string' || names.indexOf(inputName) === -1) {
        throw new ActionError('INPUT_NOT_FOUND', names.length
          ? `block #${args.targetBlockIndex} (${dest.opcode}) has inputs ${names.join(', ')}; give one as placement.inputName`
          : `block #${args.targetBlockIndex} (${dest.opcode}) has no inputs`, {inputs: names});
      }
      if (!sourceShape.reporter) {
        throw new ActionError('CONNECTION_MISMATCH', `block #${args.sourceBlockIndex} (${source.opcode}) is not a reporter; only reporters and booleans go into inputs`);
      }
      const spec = destShape.inputs.find((i) => i.name === inputName);
      if (spec.boolean && !sourceShape.boolean) {
        throw new ActionError('CONNECTION_MISMATCH', `input ${inputName} of block #${args.targetBlockIndex} takes a boolean (hexagonal) block; ${source.opcode} is a round reporter`);
      }
      unplug(blocks, source.id, false);
      const input = blocks.getBlock(dest.id).inputs[inputName];
      let unplugged = null;
      if (input && input.block && input.block !== input.shadow) {
        unplugged = input.block;
        unplug(blocks, unplugged, false);
      }
      attach(blocks, source.id, dest.id, inputName);
      return result(source, unplugged ? {detachedBlockId: unplugged} : null);
    }

    function wrap(blocks, source, sourceShape, dest, destShape, args) {
      const slots = statementInputs(sourceShape);
      if (slots.indexOf('SUBSTACK') === -1 || !sourceShape.previous) {
        throw new ActionError('CONNECTION_MISMATCH', `block #${args.sourceBlockIndex} (${source.opcode}) is not a C block and cannot wrap`);
      }
      if (source.inputs.SUBSTACK && source.inputs.SUBSTACK.block) {
        throw new ActionError('INVALID_ARG', `block #${args.sourceBlockIndex} already holds blocks in SUBSTACK; wrap needs an empty C block`);
      }
      if (!destShape.previous) {
        throw new ActionError('CONNECTION_MISMATCH', `block #${args.targetBlockIndex} is a hat block; wrap the block under it instead`);
      }
      unplug(blocks, source.id, true);
      takePlace(blocks, source.id, dest.id);
      attach(blocks, dest.id, source.id, 'SUBSTACK');
      return result(source);
    }

    function detachBlocks(args) {
      const target = editingTarget();
      const blocks = target.blocks;
      const id = requireIndex(args, 'blockIndex', indexMap(target));
      const block = blocks.getBlock(id);
      if (!block.parent) return {detached: false, reason: 'already the first block of its script'};
      unplug(blocks, id, false);
      changed();
      return {detached: true, blockId: id};
    }

    function deleteBlock(args) {
      const target = editingTarget();
      const blocks = target.blocks;
      const id = requireIndex(args, 'blockIndex', indexMap(target));
      const block = blocks.getBlock(id);
      if (block.parent) unplug(blocks, id, false);
      const chain = [];
      for (let cursor = id; cursor; cursor = blocks.getBlock(cursor).next) chain.push(cursor);
      let deleted = 0;
      for (const each of chain.reverse()) {
        deleted += countTree(blocks, each);
        const parent = blocks.getBlock(each).parent;
        if (parent) blocks.moveBlock({id: each, oldParent: parent, newCoordinate: {x: 0, y: 0}});
        blocks.deleteBlock(each);
      }
      changed();
      return {deleted: deleted};
    }

    function countTree(blocks, id) {
      const block = blocks.getBlock(id);
      let n = block.shadow ? 0 : 1;
      for (const input of Object.values(block.inputs)) {
        if (input.block && input.block !== input.shadow) n += countChain(blocks, input.block);
      }
      return n;
    }

    function countChain(blocks, id) {
      let n = 0;
      for (let cursor = id; cursor; cursor = blocks.getBlock(cursor).next) n += countTree(blocks, cursor);
      return n;
    }

    function broadcastByName(name, create) {
      const existing = variablesInScope(editingTarget(), 'broadcast_msg').find((e) => e.variable.name === name);
      if (existing) return existing.variable;
      if (!create) return null;
      const id = newId('msg');
      stage().createVariable(id, name, 'broadcast_msg');
      return stage().variables[id];
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
          throw new ActionError('INVALID_ARG', `${quote(value)} is not a choice of ${fieldName}; choices: ${options.map((o) => quote(o.text)).join(', ')}`,
            {choices: options.map((o) => o.text)});
        }
        return {value: hit.value};
      } finally {
        block.dispose(false);
      }
    }

    function setVariableField(blocks, block, fieldName, value, target) {
      const type = fieldName === 'LIST' ? 'list' : '';
      const entry = variablesInScope(target, type).find((e) => e.variable.name === value);
      if (!entry) {
        throw new ActionError('NOT_FOUND', `no ${type ? 'list' : 'variable'} named ${quote(value)} in scope`,
          {available: variablesInScope(target, type).map((e) => e.variable.name)});
      }
      block.fields[fieldName].value = entry.variable.name;
      block.fields[fieldName].id = entry.variable.id;
    }

    function setBlockField(args) {
      const target = editingTarget();
      const blocks = target.blocks;
      const id = requireIndex(args, 'blockIndex', indexMap(target));
      const fieldName = requireString(args, 'fieldName');
      if (typeof args.value !== 'string' && typeof args.value !== 'number') throw new ActionError('INVALID_ARG', 'value must be a string or a number');
      if (typeof args.value === 'number' && !Number.isFinite(args.value)) throw new ActionError('INVALID_ARG', 'value must be a finite number');
      const value = String(args.value);
      if (value.length > 10000) throw new ActionError('INVALID_ARG', 'value is longer than 10000 characters');
      const block = blocks.getBlock(id);
      if (Object.prototype.hasOwnProperty.call(block.fields, fieldName)) {
        if (fieldName === 'VARIABLE' || fieldName === 'LIST') {
          setVariableField(blocks, block, fieldName, value, target);
        } else if (fieldName === 'BROADCAST_OPTION') {
          const message = broadcastByName(value, true);
          block.fields[fieldName].value = message.name;
          block.fields[fieldName].id = message.id;
        } else {
          const match = matchChoice(block.opcode, fieldName, value, target);
          block.fields[fieldName].value = match && !match.free ? match.value : value;
        }
        changed();
        return {blockId: id, field: fieldName, value: block.fields[fieldName].value};
      }
      if (!Object.prototype.hasOwnProperty.call(block.inputs, fieldName)) {
        const shape = shapeOf(block.opcode);
        const inputs = shape ? valueInputs(shape) : Object.keys(block.inputs);
        throw new ActionError('INPUT_NOT_FOUND', `block #${args.blockIndex} (${block.opcode}) has no field or input ${quote(fieldName)}; fields: ${Object.keys(block.fields).join(', ') || 'none'}; inputs: ${inputs.join(', ') || 'none'}`,
          {fields: Object.keys(block.fields), inputs: inputs});
      }
      const input = block.inputs[fieldName];
      if (input.block && input.block !== input.shadow) {
        throw new ActionError('INVALID_STATE', `input ${fieldName} holds a block; detach it before typing a value`);
      }
      if (!input.shadow) {
        const shape = shapeOf(block.opcode);
        const spec = shape && shape.inputs.find((i) => i.name === fieldName);
        if (spec && (spec.boolean || spec.kind === 'statement')) {
          throw new ActionError('INVALID_ARG', `input ${fieldName} takes a block, not a typed value`);
        }
        createShadow(blocks, block, fieldName, value);
        changed();
        return {blockId: id, input: fieldName, value: value};
      }
      const shadow = blocks.getBlock(input.shadow);
      const shadowField = Object.keys(shadow.fields)[0];
      if (!shadowField) throw new ActionError('SET_FAILED', `input ${fieldName} has no editable value`);
      if (NUMERIC_SHADOWS.indexOf(shadow.opcode) !== -1) {
        if (value.trim() === '' || isNaN(Number(value))) throw new ActionError('INVALID_ARG', `input ${fieldName} takes a number, not ${quote(value)}`);
        shadow.fields[shadowField].value = value.trim();
      } else if (shadow.opcode === 'event_broadcast_menu') {
        const message = broadcastByName(value, true);
        shadow.fields[shadowField].value = message.name;
        shadow.fields[shadowField].id = message.id;
      } else if (shadow.opcode === 'colour_picker') {
        if (!/^#[0-9a-fA-F]{6}$/.test(value)) throw new ActionError('INVALID_ARG', `input ${fieldName} takes a colour like "#ff0000"`);
        shadow.fields[shadowField].value = value.toLowerCase();
      } else if (shadow.opcode === 'text') {
        shadow.fields[shadowField].value = value;
      } else {
        const match = matchChoice(shadow.opcode, shadowField, value, target);
        shadow.fields[shadowField].value = match && !match.free ? match.value : value;
      }
      changed();
      return {blockId: id, input: fieldName, value: shadow.fields[shadowField].value};
    }

    function createShadow(blocks, block, inputName, value) {
      const numeric = value.trim() !== '' && !isNaN(Number(value));
      const id = newId('s');
      blocks.createBlock({
        id: id, opcode: numeric ? 'math_number' : 'text', inputs: {}, next: null, topLevel: false, parent: block.id, shadow: true,
        fields: numeric ? {NUM: {name: 'NUM', value: value.trim()}} : {TEXT: {name: 'TEXT', value: value}}
      });
      block.inputs[inputName] = {name: inputName, block: id, shadow: id};
    }

    const apis = {
      select_sprite: selectSprite,
      select_stage: selectStage,
      add_variable: (args) => addVariable(args, ''),
      add_list: (args) => addVariable(args, 'list'),
      add_block: addBlock,
      connect_blocks: connectBlocks,
      detach_blocks: detachBlocks,
      set_block_field: setBlockField,
      delete_block: deleteBlock
    };

    function execute(request) {
      const api = request.api;
      const args = request.args === undefined || request.args === null ? {} : request.args;
      const started = ctx.realNow();
      try {
        if (typeof api !== 'string' || !Object.prototype.hasOwnProperty.call(apis, api)) {
          throw new ActionError('UNKNOWN_API', `unknown api ${typeof api === 'string' ? quote(api.slice(0, 80)) : 'value'}; apis: ${Object.keys(apis).join(', ')}, done, failed`);
        }
        if (typeof args !== 'object' || Array.isArray(args)) throw new ActionError('INVALID_ARG', 'args must be an object');
        const data = apis[api](args);
        return {success: true, data: data, error: null, durationMs: ctx.realNow() - started};
      } catch (reason) {
        if (reason instanceof ctx.BridgeFailure) throw reason;
        const error = reason instanceof ActionError
          ? {code: reason.code, message: reason.message, details: reason.details}
          : {code: 'INTERNAL_ERROR', message: `${reason && reason.name}: ${reason && reason.message}`, details: null};
        return {success: false, data: null, error: error, durationMs: ctx.realNow() - started};
      }
    }

    // Every block add_block can create for the editing target, with its shape, inputs and fields:
    // the block catalog of an agent's system prompt, read from the editor's own definitions.
    function catalog() {
      const target = editingTarget();
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

    function syncWorkspace() {
      vm().emitWorkspaceUpdate();
      return {synced: true};
    }

    return {
      compositeObserve: () => observe(),
      compositeExecute: (args) => execute(args),
      compositeSyncWorkspace: () => syncWorkspace(),
      compositeCatalog: () => catalog(),
      // Read-only: the block id behind every index of the editing target ([null, id of #1, ...]).
      compositeBlockIds: () => ({ids: indexMap(editingTarget())})
    };
  }

  const modules = window.__scratchworldModules = window.__scratchworldModules || [];
  modules.push(factory);
})();
