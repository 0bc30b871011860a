/*
 * Seeded page randomness, so that a verdict that depends on random numbers can be replayed.
 *
 * Every evaluation draws `Math.random` from a generator seeded with its job's seed (see
 * workers/contract/_evaluation_seed.py), and an agent's page from the same seed during its episode
 * (bridge.js, `seedRandom`): the VM's "pick random", clones' ids and the script's own draws all
 * follow it (in two streams, see `seed`); the flake finder varies the seed on purpose. lateness.js
 * draws its seeded timer lateness from the same generator. bridge.js takes the controller from
 * `window.__scratchworldRandom` (and deletes it).
 */
(function () {
  'use strict';

  // What every seed given to the page must be: all of mulberry32's state, nothing beyond it.
  const isSeed = (value) => Number.isInteger(value) && value >= 0 && value < 2 ** 32;

  // mulberry32: 32 bits of state, uniform in [0, 1), the same sequence for the same seed everywhere.
  function generator(seed) {
    let state = seed >>> 0;
    return function random() {
      state = (state + 0x6d2b79f5) >>> 0;
      let t = state;
      t = Math.imul(t ^ (t >>> 15), t | 1);
      t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
      return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
    };
  }

  /**
   * `Math.random` from `seed` on; returns the undo (the generator in place before). The VM's blocks
   * (run inside the sequencer's `stepThreads`) draw from a stream of their own, so that what the GUI
   * draws meanwhile (Blockly ids, the loader's tips: their count varies between a fresh and a reused
   * page) does not shift the project's random numbers; the script and the GUI share the other stream.
   */
  function seed(value, runtime) {
    const pageStream = generator(value ^ 0x9e3779b9);
    const vmStream = generator(value);
    const sequencer = runtime.sequencer;
    const hadOwn = Object.prototype.hasOwnProperty.call(sequencer, 'stepThreads');
    const stepThreads = sequencer.stepThreads;
    sequencer.stepThreads = function () {
      const outside = Math.random;
      // A script that fixed Math.random itself (Harness.withRandom) has the VM draw from what it set.
      if (outside !== pageStream) return stepThreads.apply(this, arguments);
      Math.random = vmStream;
      try {
        return stepThreads.apply(this, arguments);
      } finally {
        Math.random = outside;
      }
    };
    const before = Math.random; // the browser's, or an episode's seeded stream under an evaluation's
    Math.random = pageStream;
    return () => {
      Math.random = before;
      if (hadOwn) sequencer.stepThreads = stepThreads;
      else delete sequencer.stepThreads;
    };
  }

  window.__scratchworldRandom = Object.freeze({generator, seed, isSeed});
})();
