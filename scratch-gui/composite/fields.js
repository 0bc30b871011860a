/*
 * `set_block_field`: a field's value (dropdown choices matched by value, then text, then
 * case-insensitively; variables, lists and messages by name) or a typed value in an input's
 * shadow (numbers checked, colours normalised, a missing shadow created).
 */
scratchworldModule({name: 'composite/fields', requires: ['composite/arguments', 'composite/target', 'composite/catalog', 'composite/numbering', 'composite/connect'], create(ctx, checks, editing, catalog, numbering, connecting) {
  'use strict';

  function broadcastByName(name, create) {
    const existing = editing.variablesInScope(editing.target(), 'broadcast_msg').find((e) => e.variable.name === name);
    if (existing) return existing.variable;
    if (!create) return null;
    const id = editing.newId('msg');
    editing.stage().createVariable(id, name, 'broadcast_msg');
    return editing.stage().variables[id];
  }

  function setVariableField(blocks, block, fieldName, value, target) {
    const type = fieldName === 'LIST' ? 'list' : '';
    const entry = editing.variablesInScope(target, type).find((e) => e.variable.name === value);
    if (!entry) {
      throw new checks.ActionError('NOT_FOUND', `no ${type ? 'list' : 'variable'} named ${checks.quote(value)} in scope`,
        {available: editing.variablesInScope(target, type).map((e) => e.variable.name)});
    }
    block.fields[fieldName].value = entry.variable.name;
    block.fields[fieldName].id = entry.variable.id;
  }

  function setBlockField(args) {
    const target = editing.target();
    const blocks = target.blocks;
    const id = checks.requireIndex(args, 'blockIndex', numbering.indexMap(target));
    const fieldName = checks.requireString(args, 'fieldName');
    if (typeof args.value !== 'string' && typeof args.value !== 'number') throw new checks.ActionError('INVALID_ARG', 'value must be a string or a number');
    if (typeof args.value === 'number' && !Number.isFinite(args.value)) throw new checks.ActionError('INVALID_ARG', 'value must be a finite number');
    const value = String(args.value);
    if (value.length > 10000) throw new checks.ActionError('INVALID_ARG', 'value is longer than 10000 characters');
    const block = blocks.getBlock(id);
    if (Object.prototype.hasOwnProperty.call(block.fields, fieldName)) {
      if (fieldName === 'VARIABLE' || fieldName === 'LIST') {
        setVariableField(blocks, block, fieldName, value, target);
      } else if (fieldName === 'BROADCAST_OPTION') {
        const message = broadcastByName(value, true);
        block.fields[fieldName].value = message.name;
        block.fields[fieldName].id = message.id;
      } else {
        const match = catalog.matchChoice(block.opcode, fieldName, value, target);
        block.fields[fieldName].value = match && !match.free ? match.value : value;
      }
      editing.changed();
      return {blockId: id, field: fieldName, value: block.fields[fieldName].value};
    }
    if (!Object.prototype.hasOwnProperty.call(block.inputs, fieldName)) {
      const shape = catalog.shapeOf(block.opcode);
      const inputs = shape ? connecting.valueInputs(shape) : Object.keys(block.inputs);
      throw new checks.ActionError('INPUT_NOT_FOUND', `block #${args.blockIndex} (${block.opcode}) has no field or input ${checks.quote(fieldName)}; fields: ${Object.keys(block.fields).join(', ') || 'none'}; inputs: ${inputs.join(', ') || 'none'}`,
        {fields: Object.keys(block.fields), inputs: inputs});
    }
    const input = block.inputs[fieldName];
    if (input.block && input.block !== input.shadow) {
      throw new checks.ActionError('INVALID_STATE', `input ${fieldName} holds a block; detach it before typing a value`);
    }
    if (!input.shadow) {
      const shape = catalog.shapeOf(block.opcode);
      const spec = shape && shape.inputs.find((i) => i.name === fieldName);
      if (spec && (spec.boolean || spec.kind === 'statement')) {
        throw new checks.ActionError('INVALID_ARG', `input ${fieldName} takes a block, not a typed value`);
      }
      createShadow(blocks, block, fieldName, value);
      editing.changed();
      return {blockId: id, input: fieldName, value: value};
    }
    const shadow = blocks.getBlock(input.shadow);
    const shadowField = Object.keys(shadow.fields)[0];
    if (!shadowField) throw new checks.ActionError('SET_FAILED', `input ${fieldName} has no editable value`);
    if (catalog.NUMERIC_SHADOWS.indexOf(shadow.opcode) !== -1) {
      if (value.trim() === '' || isNaN(Number(value))) throw new checks.ActionError('INVALID_ARG', `input ${fieldName} takes a number, not ${checks.quote(value)}`);
      shadow.fields[shadowField].value = value.trim();
    } else if (shadow.opcode === 'event_broadcast_menu') {
      const message = broadcastByName(value, true);
      shadow.fields[shadowField].value = message.name;
      shadow.fields[shadowField].id = message.id;
    } else if (shadow.opcode === 'colour_picker') {
      if (!/^#[0-9a-fA-F]{6}$/.test(value)) throw new checks.ActionError('INVALID_ARG', `input ${fieldName} takes a colour like "#ff0000"`);
      shadow.fields[shadowField].value = value.toLowerCase();
    } else if (shadow.opcode === 'text') {
      shadow.fields[shadowField].value = value;
    } else {
      const match = catalog.matchChoice(shadow.opcode, shadowField, value, target);
      shadow.fields[shadowField].value = match && !match.free ? match.value : value;
    }
    editing.changed();
    return {blockId: id, input: fieldName, value: shadow.fields[shadowField].value};
  }

  function createShadow(blocks, block, inputName, value) {
    const numeric = value.trim() !== '' && !isNaN(Number(value));
    const id = editing.newId('s');
    blocks.createBlock({
      id: id, opcode: numeric ? 'math_number' : 'text', inputs: {}, next: null, topLevel: false, parent: block.id, shadow: true,
      fields: numeric ? {NUM: {name: 'NUM', value: value.trim()}} : {TEXT: {name: 'TEXT', value: value}}
    });
    block.inputs[inputName] = {name: inputName, block: id, shadow: id};
  }

  return {setBlockField: setBlockField, broadcastByName: broadcastByName};
}});
