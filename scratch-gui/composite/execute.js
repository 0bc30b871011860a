/*
 * Composite mode's one entry for actions: `compositeExecute` runs an API call on the VM,
 * synchronously, and answers with an envelope `{success, data, error: {code, message, details}}`;
 * agent mistakes are answers with a stable code, never exceptions, and arguments are data:
 * nothing an agent sends is ever evaluated as code. The visible workspace is redrawn from the VM
 * only when asked (`compositeSyncWorkspace`): redrawing costs ~100 ms on a real project and
 * nothing in composite mode looks at it.
 */
scratchworldModule({name: 'composite/execute', requires: ['composite/arguments', 'composite/target', 'composite/connect', 'composite/fields', 'composite/edit'], create(ctx, checks, editing, connecting, fieldEdits, edits) {
  'use strict';

  const apis = {
    select_sprite: edits.selectSprite,
    select_stage: edits.selectStage,
    add_variable: (args) => edits.addVariable(args, ''),
    add_list: (args) => edits.addVariable(args, 'list'),
    add_block: edits.addBlock,
    connect_blocks: connecting.connectBlocks,
    detach_blocks: edits.detachBlocks,
    set_block_field: fieldEdits.setBlockField,
    delete_block: edits.deleteBlock
  };

  function execute(request) {
    const api = request.api;
    const args = request.args === undefined || request.args === null ? {} : request.args;
    const started = ctx.realNow();
    try {
      if (typeof api !== 'string' || !Object.prototype.hasOwnProperty.call(apis, api)) {
        throw new checks.ActionError('UNKNOWN_API', `unknown api ${typeof api === 'string' ? checks.quote(api.slice(0, 80)) : 'value'}; apis: ${Object.keys(apis).join(', ')}, done, failed`);
      }
      if (typeof args !== 'object' || Array.isArray(args)) throw new checks.ActionError('INVALID_ARG', 'args must be an object');
      const data = apis[api](args);
      return {success: true, data: data, error: null, durationMs: ctx.realNow() - started};
    } catch (reason) {
      if (reason instanceof ctx.BridgeFailure) throw reason;
      const error = reason instanceof checks.ActionError
        ? {code: reason.code, message: reason.message, details: reason.details}
        : {code: 'INTERNAL_ERROR', message: `${reason && reason.name}: ${reason && reason.message}`, details: null};
      return {success: false, data: null, error: error, durationMs: ctx.realNow() - started};
    }
  }

  function syncWorkspace() {
    editing.vm().emitWorkspaceUpdate();
    return {synced: true};
  }

  return {
    api: {compositeExecute: (args) => execute(args), compositeSyncWorkspace: () => syncWorkspace()},
  };
}});
