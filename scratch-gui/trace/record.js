/*
 * The observable trace of an evaluation: after every VM frame (step), what a user could observe
 * (trace/observe.js, trace/happenings.js), kept as the fields that changed since the last frame
 * recorded. Asked for with `evaluate`'s `observableTrace: {maxChars}`; the bridge starts it right
 * before the script runs and stops it when the script is done, before the VM is stopped. Python takes
 * it with `takeObservableTrace` (also after a script that failed or timed out).
 *
 * The trace: {frames: [{frame, targets: {key: {field: value}}, removed?: [key]}], steps, truncatedAt,
 * chars, recordMs (real ms the recording took)}. Frame 0 is the state when the script starts (every field of every target), frame n the state
 * after the n-th VM step, recorded only when something changed. Targets are keyed by name, the stage
 * as "Stage", clones as "<sprite>#<n>" in creation order. Sounds started in a frame are the event field
 * `sounds` of the target that played them; the stage also has `pen` (counts and digest, running) and
 * `question` (the ask prompt). Once the JSON of the frames would pass `maxChars`, recording stops and
 * `truncatedAt` names the first frame left out.
 */
scratchworldModule({name: 'trace/record', requires: ['trace/observe', 'trace/happenings'], create(ctx, observe, happenings) {
  'use strict';

  const MIN_CHARS = 1000;
  const MAX_CHARS = 16 * 1024 * 1024;
  let last = null; // the last evaluation's trace, until Python takes it
  let recording = null; // the recorder of the evaluation under way

  function maxCharsOf(options) {
    const maxChars = options.maxChars;
    if (!(Number.isInteger(maxChars) && maxChars >= MIN_CHARS && maxChars <= MAX_CHARS)) {
      throw new ctx.BridgeFailure('bad_request', `observableTrace.maxChars must be an integer from ${MIN_CHARS} to ${MAX_CHARS}`);
    }
    return maxChars;
  }

  function recorder(vm, maxChars) {
    const runtime = vm.runtime;
    const keys = new WeakMap();
    const clonesMade = new Map(); // sprite name -> clones keyed so far
    const keyOf = (target) => {
      let key = keys.get(target);
      if (key === undefined) {
        const name = target.isStage ? 'Stage' : target.sprite.name;
        if (target.isOriginal) key = name;
        else {
          const made = (clonesMade.get(name) || 0) + 1;
          clonesMade.set(name, made);
          key = `${name}#${made}`;
        }
        keys.set(target, key);
      }
      return key;
    };
    const onCreated = (target) => { keyOf(target); }; // creation order, even for clones created in one frame
    const frames = [];
    const previous = new Map(); // key -> {field: JSON text}
    let chars = 0;
    let steps = 0;
    let truncatedAt = null;
    let recordMs = 0; // real time spent recording (what the trace costs; not part of it)
    let events = null;
    let undoStep = null;

    function record(frame) {
      if (truncatedAt !== null) return;
      const startedMs = ctx.realNow();
      try {
        take(frame);
      } finally {
        recordMs += ctx.realNow() - startedMs;
      }
    }

    function take(frame) {
      const now = observe.snapshot(vm, keyOf);
      const happened = events.take();
      const stage = now.get('Stage');
      if (stage) Object.assign(stage, {pen: happened.pen, question: happened.question});
      const changed = {};
      let any = false;
      for (const [key, fields] of now) {
        const before = previous.get(key) || {};
        const texts = {};
        let delta = null;
        for (const name of Object.keys(fields)) {
          texts[name] = JSON.stringify(fields[name]);
          if (before[name] !== texts[name]) (delta = delta || {})[name] = fields[name];
        }
        previous.set(key, texts);
        if (delta) { changed[key] = delta; any = true; }
      }
      for (const [key, names] of happened.sounds) { // a clone may play and go in one frame
        (changed[key] = changed[key] || {}).sounds = names;
        any = true;
      }
      const removed = [...previous.keys()].filter((key) => !now.has(key));
      for (const key of removed) previous.delete(key);
      if (!any && removed.length === 0) return;
      const entry = removed.length ? {frame, targets: changed, removed} : {frame, targets: changed};
      const size = JSON.stringify(entry).length + 1;
      if (chars + size > maxChars) {
        truncatedAt = frame;
        return;
      }
      chars += size;
      frames.push(entry);
    }

    // Runs the VM's step, then records: the frame loop calls `this._step()` (harness.js wraps it the same way).
    function wrapStep() {
      const hadOwn = Object.prototype.hasOwnProperty.call(runtime, '_step');
      const step = runtime._step;
      let active = true;
      const wrapper = function () {
        const result = step.apply(this, arguments);
        if (active) {
          steps += 1;
          record(steps);
        }
        return result;
      };
      runtime._step = wrapper;
      return () => {
        active = false;
        if (runtime._step !== wrapper) return; // wrapped again and left so: ours passes through
        if (hadOwn) runtime._step = step;
        else delete runtime._step;
      };
    }

    return {
      steps: () => steps,
      start() {
        runtime.on('targetWasCreated', onCreated);
        events = happenings.start(vm, keyOf);
        record(0);
        undoStep = wrapStep();
      },
      stop() {
        if (undoStep) undoStep();
        if (events) events.stop();
        runtime.removeListener('targetWasCreated', onCreated);
        return {frames, steps, truncatedAt, chars, recordMs};
      },
    };
  }

  // Called by `evaluate` with its arguments, before anything starts: null, or the trace's start and stop.
  ctx.onEvaluation((vm, args) => {
    last = null;
    if (args.observableTrace == null) return null;
    const rec = recorder(vm, maxCharsOf(args.observableTrace));
    return {
      start: () => { recording = rec; rec.start(); },
      stop: () => { recording = null; last = rec.stop(); },
    };
  });
  ctx.onProjectLoaded(() => { last = null; });

  return {
    // The frame the trace under way is at (VM steps since the script started), or null when none records.
    frame: () => (recording === null ? null : recording.steps()),
    api: {
      takeObservableTrace: () => {
        const trace = last;
        last = null;
        return trace;
      },
    },
  };
}});
