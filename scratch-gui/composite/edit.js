/*
 * The other composite actions: select a sprite or the stage, add a variable or a list, add a
 * block (from the editor's toolbox template, completed by Blockly, its variable and message
 * fields bound), detach a block and delete one with what it holds.
 */
scratchworldModule({name: 'composite/edit', requires: ['blockly', 'composite/arguments', 'composite/target', 'composite/catalog', 'composite/numbering', 'composite/structure', 'composite/fields'], create(ctx, blockly, checks, editing, catalog, numbering, structure, fieldEdits) {
  'use strict';

  function selectSprite(args) {
    const name = checks.requireString(args, 'name');
    const sprites = editing.vm().runtime.targets.filter((t) => t.isOriginal && !t.isStage);
    const match = sprites.find((t) => t.getName() === name) || sprites.find((t) => t.getName().toLowerCase() === name.toLowerCase());
    if (!match) {
      throw new checks.ActionError('NOT_FOUND', `no sprite named ${checks.quote(name)}; sprites: ${sprites.map((t) => checks.quote(t.getName())).join(', ') || 'none'}`,
        {sprites: sprites.map((t) => t.getName())});
    }
    editing.vm().setEditingTarget(match.id);
    return {editingTarget: match.getName()};
  }

  function selectStage() {
    editing.vm().setEditingTarget(editing.stage().id);
    return {editingTarget: editing.stage().getName()};
  }

  function addVariable(args, type) {
    const name = checks.requireString(args, 'name');
    const scope = checks.requireScope(args);
    const target = editing.target();
    if (scope === 'sprite' && target.isStage) throw new checks.ActionError('INVALID_ARG', 'the stage has only global variables: use scope "all"');
    const existing = editing.variablesInScope(target, type).find((e) => e.variable.name === name);
    if (existing) return {created: {name: name, id: existing.variable.id, scope: existing.scope, created: false}};
    if (scope === 'all') {
      const clash = editing.vm().runtime.targets.find((t) => !t.isStage && Object.values(t.variables).some((v) => v.name === name && v.type === type));
      if (clash) throw new checks.ActionError('INVALID_ARG', `sprite ${checks.quote(clash.getName())} already has a local ${type ? 'list' : 'variable'} named ${checks.quote(name)}`);
    }
    const owner = scope === 'all' ? editing.stage() : target;
    const id = editing.newId('var');
    owner.createVariable(id, name, type);
    editing.changed();
    return {created: {name: name, id: id, scope: scope, created: true}};
  }

  function bindVariable(target, element, fieldName, type, wanted, required) {
    const fields = [...element.getElementsByTagName('field')].filter((f) => f.getAttribute('name') === fieldName);
    if (!fields.length) return null;
    const candidates = editing.variablesInScope(target, type);
    const what = type === 'list' ? 'list' : 'variable';
    let chosen = null;
    if (wanted !== undefined) {
      if (typeof wanted !== 'string' || !wanted.length) throw new checks.ActionError('INVALID_ARG', `creation.${what}Name must be a non-empty string`);
      chosen = candidates.find((e) => e.variable.name === wanted);
      if (!chosen) {
        throw new checks.ActionError('NOT_FOUND', `no ${what} named ${checks.quote(wanted)} in scope; create it with add_${what} first`,
          {available: candidates.map((e) => e.variable.name)});
      }
    } else if (required) {
      throw new checks.ActionError('INVALID_ARG', `this block needs creation.${what}Name`, {available: candidates.map((e) => e.variable.name)});
    } else {
      chosen = candidates[0];
      if (!chosen) throw new checks.ActionError('NOT_FOUND', `no ${what} exists yet; create one with add_${what} first`);
    }
    for (const field of fields) {
      field.setAttribute('id', chosen.variable.id);
      field.setAttribute('variabletype', type);
      field.textContent = chosen.variable.name;
    }
    return chosen.variable.name;
  }

  // Broadcast menus in toolbox entries name a message the project may not have yet.
  function ensureMessages(element) {
    for (const field of element.getElementsByTagName('field')) {
      if (field.getAttribute('variabletype') !== 'broadcast_msg') continue;
      const existing = editing.variablesInScope(editing.target(), 'broadcast_msg');
      const name = field.textContent || (existing.length ? existing[0].variable.name : 'message1');
      const message = fieldEdits.broadcastByName(name, true);
      field.setAttribute('id', message.id);
      field.textContent = message.name;
    }
  }

  function addBlock(args) {
    const opcode = checks.requireString(args, 'blockType');
    const creation = args.creation === undefined ? {} : args.creation;
    if (typeof creation !== 'object' || creation === null || Array.isArray(creation)) throw new checks.ActionError('INVALID_ARG', 'creation must be an object');
    const target = editing.target();
    const templates = catalog.toolboxTemplates(target);
    let element;
    if (Object.prototype.hasOwnProperty.call(catalog.TEMPLATES, opcode)) {
      element = new DOMParser().parseFromString(catalog.TEMPLATES[opcode], 'text/xml').documentElement;
    } else if (templates.has(opcode) && catalog.inCatalog(opcode)) {
      element = catalog.completeTemplate(templates.get(opcode));
    } else {
      if (target.isStage && catalog.inCatalog(opcode) && blockly.scratchBlocks().Blocks[opcode]) {
        throw new checks.ActionError('UNSUPPORTED', `${opcode} is not available for the stage; select a sprite first`);
      }
      const similar = [...catalog.catalogFor(target)].filter((o) => o.includes(opcode.split('_').pop() || opcode)).slice(0, 8);
      throw new checks.ActionError('INVALID_ARG', `unknown block type ${checks.quote(opcode)}`, {similar: similar});
    }
    catalog.stripWhitespace(element);
    ensureMessages(element);
    const variableName = bindVariable(target, element, 'VARIABLE', '', creation.variableName, opcode === 'data_variable');
    const listName = bindVariable(target, element, 'LIST', 'list', creation.listName, opcode === 'data_listcontents');
    const blocks = target.blocks;
    const ids = [];
    for (const node of [element, ...element.querySelectorAll('block,shadow')]) {
      const id = editing.newId('b');
      node.setAttribute('id', id);
      ids.push(id);
    }
    element.setAttribute('x', '400');
    element.setAttribute('y', String(structure.bottomY(blocks) + 120));
    blocks.blocklyListen({type: 'create', blockId: ids[0], xml: element});
    if (!blocks.getBlock(ids[0])) throw new checks.ActionError('INTERNAL_ERROR', `the VM did not create ${opcode}`);
    editing.changed();
    const byIndex = numbering.indexMap(target);
    const data = {blockId: ids[0], index: byIndex.indexOf(ids[0]), opcode: opcode};
    if (variableName !== null) data.variable = variableName;
    if (listName !== null) data.list = listName;
    return data;
  }

  function detachBlocks(args) {
    const target = editing.target();
    const blocks = target.blocks;
    const id = checks.requireIndex(args, 'blockIndex', numbering.indexMap(target));
    const block = blocks.getBlock(id);
    if (!block.parent) return {detached: false, reason: 'already the first block of its script'};
    structure.unplug(blocks, id, false);
    editing.changed();
    return {detached: true, blockId: id};
  }

  function deleteBlock(args) {
    const target = editing.target();
    const blocks = target.blocks;
    const id = checks.requireIndex(args, 'blockIndex', numbering.indexMap(target));
    const block = blocks.getBlock(id);
    if (block.parent) structure.unplug(blocks, id, false);
    const chain = [];
    for (let cursor = id; cursor; cursor = blocks.getBlock(cursor).next) chain.push(cursor);
    let deleted = 0;
    for (const each of chain.reverse()) {
      deleted += structure.countTree(blocks, each);
      const parent = blocks.getBlock(each).parent;
      if (parent) blocks.moveBlock({id: each, oldParent: parent, newCoordinate: {x: 0, y: 0}});
      blocks.deleteBlock(each);
    }
    editing.changed();
    return {deleted: deleted};
  }

  return {
    selectSprite: selectSprite, selectStage: selectStage, addVariable: addVariable, addBlock: addBlock,
    detachBlocks: detachBlocks, deleteBlock: deleteBlock,
  };
}});
