/*
 * What `evaluate` makes of a task's script and of its arguments: the script's source as a CommonJS-style module
 * (`loadModule`), its result as bounded JSON text (`toJson`), and the checked perturbation (`perturbationOf`) and
 * frame timing (`frameTimingOf`) the page clock runs it with. Each bad input is a `bad_request`, `script_invalid` or
 * `result_invalid` failure that names what was wrong, before anything runs or after it ran.
 */
scratchworldModule({name: 'evaluation/script', create(ctx) {
  'use strict';

  const BridgeFailure = ctx.BridgeFailure;
  // Results larger than this are refused rather than shipped across the protocol.
  const MAX_RESULT_CHARS = 2 * 1024 * 1024;
  const LATENESS_MODELS = ['fixed', 'uniform'];

  // CommonJS-style module: the source sees `module`, `exports` and a `require` that only knows
  // the suite's helper module (upstream scripts reach it as a global, some may require it).
  function loadModule(source, name, helper) {
    if (typeof source !== 'string') throw new BridgeFailure('bad_request', `${name}: source must be a string`);
    const module = {exports: {}};
    const require = (id) => {
      if (helper && /(^|\/)evaluation_utils(\.js)?$|(^|\/)helper(\.js)?$/.test(id)) return helper;
      throw new Error(`require('${id}') is not available to evaluation scripts`);
    };
    let factory;
    try {
      factory = new Function('module', 'exports', 'require', `${source}\n//# sourceURL=${encodeURI(name)}`);
    } catch (reason) {
      throw new BridgeFailure('script_invalid', `${name} does not parse: ${ctx.describe(reason)}`);
    }
    try {
      factory(module, module.exports, require);
    } catch (reason) {
      throw new BridgeFailure('script_invalid', `${name} threw while loading: ${ctx.describe(reason)}`);
    }
    return module.exports;
  }

  // Turns whatever a script returned into JSON text: cycles and functions are dropped, not fatal.
  function toJson(value, scriptName) {
    const seen = new WeakSet();
    let text;
    try {
      text = JSON.stringify(value === undefined ? null : value, (key, item) => {
        if (typeof item === 'function' || typeof item === 'symbol') return undefined;
        if (typeof item === 'bigint') return Number(item);
        if (item && typeof item === 'object') {
          if (seen.has(item)) return '[circular]';
          seen.add(item);
        }
        return item;
      });
    } catch (reason) {
      throw new BridgeFailure('result_invalid', `${scriptName}: the result cannot be serialised: ${ctx.describe(reason)}`);
    }
    if (text.length > MAX_RESULT_CHARS) {
      throw new BridgeFailure(
        'result_invalid', `${scriptName}: the result is ${text.length} characters long (limit ${MAX_RESULT_CHARS})`);
    }
    return text;
  }

  // The perturbation of an evaluation (`scratchworld flakes`), checked: null, or
  // {randomSeed, phaseMs, lateness: null | {model, ms, seed}}. Phase and lateness need the virtual clock.
  function perturbationOf(value, clockMode) {
    if (value == null) return null;
    const bad = (message) => new BridgeFailure('bad_request', `perturbation: ${message}`);
    const seed = value.randomSeed;
    if (!ctx.isSeed(seed)) throw bad('randomSeed must be an integer from 0 to 2^32 - 1');
    const phaseMs = value.phaseMs == null ? 0 : value.phaseMs;
    if (!(typeof phaseMs === 'number' && phaseMs >= 0 && phaseMs < 1000)) throw bad('phaseMs must be from 0 to under 1000');
    const late = value.lateness == null ? null : value.lateness;
    if (late !== null) {
      if (!LATENESS_MODELS.includes(late.model)) throw bad(`lateness.model must be one of ${LATENESS_MODELS.join(', ')}`);
      if (!(typeof late.ms === 'number' && late.ms >= 0 && late.ms <= 1000)) throw bad('lateness.ms must be from 0 to 1000');
      if (!ctx.isSeed(late.seed)) throw bad('lateness.seed must be an integer from 0 to 2^32 - 1');
      if (late.ms > 0 && clockMode !== 'virtual') throw bad('timer lateness needs the virtual clock');
    }
    if (phaseMs > 0 && clockMode !== 'virtual') throw bad('a frame phase needs the virtual clock');
    return {randomSeed: seed, phaseMs: phaseMs, lateness: late};
  }

  // The calibrated frame timing (clock.js): null, or {fixedMs, perBlockMs, perRedrawMs}; virtual clock only.
  function frameTimingOf(value, clockMode) {
    if (value == null) return null;
    for (const name of ['fixedMs', 'perBlockMs', 'perRedrawMs']) {
      const ms = value[name];
      if (!(typeof ms === 'number' && ms >= 0 && ms <= 1000)) throw new BridgeFailure('bad_request', `frameTiming.${name} must be a number from 0 to 1000`);
    }
    if (clockMode !== 'virtual') throw new BridgeFailure('bad_request', 'a frame timing model needs the virtual clock');
    return {model: 'calibrated', fixedMs: value.fixedMs, perBlockMs: value.perBlockMs, perRedrawMs: value.perRedrawMs};
  }

  return {loadModule, toJson, perturbationOf, frameTimingOf};
}});
