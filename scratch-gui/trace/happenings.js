/*
 * What happens between two snapshots that a user sees or hears but no VM state keeps (the observable
 * trace, trace/record.js): the pen's drawing, sounds started and the ask prompt. The pen is counted at
 * the renderer's pen operations every pen block ends in (lines, dots, stamps, clears) with a digest of
 * their arguments (where, colour, size; what a stamp printed), so no pixel is read; sounds at the
 * sound bank every sound block plays through. The hooks are put back by `stop`.
 */
scratchworldModule({name: 'trace/happenings', requires: ['trace/observe'], create(ctx, observe) {
  'use strict';

  // Replaces object[name] with a function that calls `before(...args)` first; returns the undo.
  function hook(object, name, before) {
    const hadOwn = Object.prototype.hasOwnProperty.call(object, name);
    const original = object[name];
    let active = true;
    const wrapper = function () {
      if (active) before.apply(this, arguments);
      return original.apply(this, arguments);
    };
    object[name] = wrapper;
    return () => {
      active = false; // wrapped again by someone who did not unwrap: ours stays, passing calls through
      if (object[name] !== wrapper) return;
      if (hadOwn) object[name] = original;
      else delete object[name];
    };
  }

  // FNV-1a over text: a running digest of the pen's operations, the same in every run that draws the same.
  function mixed(digest, text) {
    let hash = digest;
    for (let i = 0; i < text.length; i++) {
      hash ^= text.charCodeAt(i);
      hash = Math.imul(hash, 0x01000193) >>> 0;
    }
    return hash;
  }

  /**
   * Starts listening; `take()` returns what happened since the last take ({pen, question, sounds: Map
   * key -> [sound names]}; pen counts and the question are running state), `stop()` ends it.
   */
  function start(vm, keyOf) {
    const runtime = vm.runtime;
    const undo = [];
    const pen = {lines: 0, dots: 0, stamps: 0, clears: 0, digest: 0x811c9dc5};
    let sounds = new Map();
    let question = null; // the ask prompt's question while it is open ('' when a visible sprite asks)
    const note = (text) => { pen.digest = mixed(pen.digest, text); };
    const renderer = runtime.renderer;
    if (renderer) {
      undo.push(hook(renderer, 'penLine', (skin, attributes, x0, y0, x1, y1) => {
        pen.lines += 1;
        note(JSON.stringify(['line', attributes.color4f, attributes.diameter, x0, y0, x1, y1]));
      }));
      undo.push(hook(renderer, 'penPoint', (skin, attributes, x, y) => {
        pen.dots += 1;
        note(JSON.stringify(['dot', attributes.color4f, attributes.diameter, x, y]));
      }));
      undo.push(hook(renderer, 'penStamp', (skin, drawableID) => {
        pen.stamps += 1;
        const target = runtime.targets.find((t) => t.drawableID === drawableID);
        note(JSON.stringify(['stamp', target ? keyOf(target) : null, target ? observe.appearance(target) : null]));
      }));
      undo.push(hook(renderer, 'penClear', () => {
        pen.clears += 1;
        note('clear');
      }));
    }
    // Every sprite's sound bank is of one class (scratch-audio's SoundBank); its prototype is patched.
    const bank = runtime.targets.map((t) => t.sprite && t.sprite.soundBank).find(Boolean);
    if (bank) {
      undo.push(hook(Object.getPrototypeOf(bank), 'playSound', (target, soundId) => {
        const sound = target && target.sprite ? target.sprite.sounds.find((s) => s.soundId === soundId) : null;
        const key = keyOf(target);
        if (!sounds.has(key)) sounds.set(key, []);
        sounds.get(key).push(sound ? sound.name : String(soundId));
      }));
    }
    const onQuestion = (text) => { question = text === null || text === undefined ? null : String(text); };
    runtime.on('QUESTION', onQuestion);
    undo.push(() => runtime.removeListener('QUESTION', onQuestion));
    return {
      take() {
        const happened = {pen: {...pen, digest: pen.digest.toString(16)}, question, sounds};
        sounds = new Map();
        return happened;
      },
      stop() {
        for (const step of undo.reverse()) step();
      },
    };
  }

  return {start};
}});
