/*
 * Composite mode's answers to agent mistakes: `ActionError` carries a stable code (INVALID_ARG,
 * NOT_FOUND, CONNECTION_MISMATCH, ...) into the `execute` envelope instead of escaping as an
 * exception; the argument checks every action shares; and the quoting that keeps any name from
 * forging a line of the observation.
 */
scratchworldModule({name: 'composite/arguments', requires: [], create(ctx) {
  'use strict';

  const MAX_NAME = 200;

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

  return {
    ActionError: ActionError, quote: quote, clean: clean,
    requireString: requireString, requireIndex: requireIndex, requireScope: requireScope,
  };
}});
