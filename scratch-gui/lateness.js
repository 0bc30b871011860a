/*
 * How late the virtual clock's repeating timers fire (clock.js applies it while a perturbed or
 * calibrated evaluation runs virtually). A model is `(parameters, random) => (timer, work) => ms`,
 * where `work` is what the VM's frame did ({blocks, redraw}) when the timer is the frame loop, and
 * null otherwise:
 *
 *  - `fixed`: every firing exactly `ms` late (`scratchworld flakes`' lateness levels);
 *  - `uniform`: drawn from [0, 2 ms) (mean `ms`) by the seeded generator of random.js;
 *  - `calibrated`: the frame loop only, late by fixedMs + perBlockMs * blocks + perRedrawMs * redraw,
 *    coefficients fitted on real runs by benchmarks/frame_lateness.py and handed in by Python;
 *    deterministic, it reads no clock.
 *
 * clock.js takes `combined` from `window.__scratchworldLateness` (and deletes it).
 */
(function () {
  'use strict';

  const seededGenerator = window.__scratchworldRandom.generator; // random.js, loaded first

  const MODELS = Object.freeze({
    fixed: (parameters) => () => parameters.ms,
    uniform: (parameters, random) => () => random() * 2 * parameters.ms,
    calibrated: (parameters) => (timer, work) => (work === null ? 0 : Math.max(0,
      parameters.fixedMs + parameters.perBlockMs * work.blocks + parameters.perRedrawMs * work.redraw)),
  });

  function latenessOf(parameters) {
    if (!parameters) return null;
    if (parameters.model !== 'calibrated' && !(parameters.ms > 0)) return null; // 0: today's exact timing
    const model = MODELS[parameters.model];
    if (!model) throw new Error(`unknown lateness model ${parameters.model}`);
    return model(parameters, seededGenerator(parameters.seed || 0));
  }

  // Several models at once (a perturbation on top of the calibrated frame timing): their sum, or null for none.
  function combined(models) {
    const parts = models.map(latenessOf).filter((part) => part !== null);
    if (parts.length === 0) return null;
    return (timer, work) => parts.reduce((total, part) => total + part(timer, work), 0);
  }

  window.__scratchworldLateness = Object.freeze({combined});
})();
