/*
 * The text observation of composite mode: the editing target, the variables and lists in its
 * scope, every target, and the pseudocode of its scripts with #n indexes, dropdown choices and
 * literal values (`compositeObserve`), in the benchmark's section layout.
 */
scratchworldModule({name: 'composite/observation', requires: ['composite/arguments', 'composite/target', 'composite/catalog', 'composite/numbering'], create(ctx, checks, editing, catalog, numbering) {
  'use strict';

  function choicesText(opcode, fieldName, target) {
    const choices = catalog.choicesOf(opcode, fieldName, target);
    if (!choices) return '';
    const key = `${fieldName.toLowerCase().replace(/_/g, '')}Options`;
    return ` {choices: ${JSON.stringify({[key]: choices})}}`;
  }

  function literalText(shadow, target) {
    const fieldNames = Object.keys(shadow.fields);
    if (!fieldNames.length) return `(${shadow.opcode})`;
    const field = shadow.fields[fieldNames[0]];
    const value = catalog.NUMERIC_SHADOWS.indexOf(shadow.opcode) !== -1 && field.value !== '' && !isNaN(Number(field.value))
      ? checks.clean(field.value) : checks.quote(field.value);
    const menu = catalog.NUMERIC_SHADOWS.indexOf(shadow.opcode) === -1 && shadow.opcode !== 'text' && shadow.opcode !== 'colour_picker';
    return `${value} (${shadow.opcode})${menu ? choicesText(shadow.opcode, fieldNames[0], target) : ''}`;
  }

  function pseudocode(target) {
    const lines = [];
    const blocks = target.blocks;
    const pad = (depth) => '  '.repeat(depth);
    const visit = (block, depth, index, isTop) => {
      const shape = catalog.shapeOf(block.opcode);
      const outside = catalog.inCatalog(block.opcode) && shape ? '' : ' (not in catalog)';
      lines.push(`${pad(depth)}#${index}${isTop ? ' [top]' : ''} ${checks.clean(block.opcode)}${outside}`);
      const fieldOrder = shape ? shape.fields.filter((f) => block.fields[f]) : [];
      for (const name of Object.keys(block.fields)) if (fieldOrder.indexOf(name) === -1) fieldOrder.push(name);
      for (const name of fieldOrder) {
        lines.push(`${pad(depth)}- field ${checks.clean(name)}: ${checks.quote(block.fields[name].value)}${choicesText(block.opcode, name, target)}`);
      }
    };
    visit.input = (block, name, depth) => lines.push(`${pad(depth)}- input ${checks.clean(name)}:`);
    visit.literal = (block, name, depth) => {
      const input = block.inputs[name];
      const shadow = input && input.shadow ? blocks.getBlock(input.shadow) : null;
      lines.push(`${pad(depth)}- input ${checks.clean(name)}: ${shadow ? literalText(shadow, target) : '(empty)'}`);
    };
    visit.statement = (block, name, depth, filled) => lines.push(`${pad(depth)}- ${checks.clean(name)}:${filled ? '' : ' (empty)'}`);
    visit.endScript = () => lines.push('');
    const count = numbering.walk(blocks, visit);
    return {text: lines.join('\n').replace(/\n+$/, ''), count: count};
  }

  function observe() {
    const target = editing.target();
    const section = (entries) => entries.length ? entries.join('; ') : 'None';
    const variables = editing.variablesInScope(target, '').map((e) => `name: ${checks.clean(e.variable.name)}, scope: ${e.scope}`);
    const lists = editing.variablesInScope(target, 'list').map((e) => `name: ${checks.clean(e.variable.name)}, scope: ${e.scope}`);
    const targets = editing.vm().runtime.targets.filter((t) => t.isOriginal).map((t) => checks.clean(t.getName()));
    const code = pseudocode(target);
    const text = [
      '## Current Editing Target', checks.clean(target.getName()), '',
      '## Target Variables In Scope', section(variables), '',
      '## Target Lists In Scope', section(lists), '',
      '## All Available Targets', targets.join(', '), '',
      '## Blocks Pseudocode', code.text || 'None'
    ].join('\n');
    const all = editing.vm().runtime.targets.filter((t) => t.isOriginal).map((t) => ({name: t.getName(), isStage: t.isStage}));
    return {text: text, editingTarget: target.getName(), blockCount: code.count, targets: all};
  }

  return {
    api: {
      compositeObserve: () => observe(),
      // Read-only: the block id behind every index of the editing target ([null, id of #1, ...]).
      compositeBlockIds: () => ({ids: numbering.indexMap(editing.target())}),
    },
  };
}});
