/*
 * The page clock: real time, except while an evaluation script runs in virtual time.
 *
 * Loaded before every other script, it replaces `Date`, `performance.now` and the timer functions
 * with versions backed by one timer table. In real mode every timer is also a native timer and the
 * clocks read the real ones, so editor start-up and agent episodes see ordinary real time. In
 * virtual mode ("frozen" time, see shared/notes/virtual-time.md) time stands still while JavaScript
 * runs and moves only when a timer fires: the earliest timer (creation order for ties, as Chromium
 * does) fires in its own task (a MessageChannel message), so promise callbacks and other tasks run
 * between two timers as they do in a browser, and the clock jumps to its due time.
 *
 * A fake clock alone would hang or slow the VM, which also measures work on the clock, so the VM
 * gets three patches (vm-clock-patches.js, installed by `attachVm`): its per-frame work budget and its
 * warp timer use the real clock; "play sound until done" ends after the sound's length in virtual time
 * (the audio clock is not a timer); in virtual mode a frame's work also stops after a pass over the
 * threads in which no block with a side effect ran, since every further pass would repeat it exactly.
 * `requestAnimationFrame` stays real: the VM steps on an interval timer and draws in its step, and
 * during our suite's evaluations only the GUI called it (0-2 times per evaluation, measured).
 *
 * An agent's page can run on the same virtual clock (`pauseVirtual`): time stands still between the
 * agent's actions, timers already due still fire (Blockly hands its events to the VM in zero-delay
 * timeouts), and `advance(ms)` lets exactly that much virtual time pass, so what an agent sees does
 * not depend on how long its model took, and a page waiting for the model costs no CPU.
 *
 * Perturbations (`scratchworld flakes`, all recorded with the verdict): `startVirtual` can start the
 * script `phaseMs` before the VM's next frame instead of right at it, and make every repeating timer
 * late by a seeded lateness model (the VM's frame loop is an interval timer, so a lateness of L ms
 * gives 1000 / (33 + L) frames per second). Both exist only in virtual time: on the real clock the
 * phase is whatever the wall clock gives, and timers are as late as the machine makes them.
 *
 * Frame timing (`frameTiming`, the `calibrated` model of lateness.js): each frame late by a linear
 * function of the work it did, counted here by the wrappers `attachVm` installs (one increment per
 * block call, no clock read). The same counts feed the frame trace benchmarks/frame_lateness.py
 * reads (`traceFrames`), which an evaluation takes back before it returns.
 *
 * Timers created during an evaluation are marked, so that a page can be reused: `drainEvaluation`
 * fires the ones still pending ahead of time and reports what keeps running (recycle.js).
 *
 * bridge.js takes the controller from `window.__scratchworldClock` (and deletes it); Python drives
 * the clock only through bridge calls.
 */
(function () {
  'use strict';

  const RealDate = window.Date;
  const realPerformanceNow = performance.now.bind(performance);
  const realSetTimeout = window.setTimeout.bind(window);
  const realClearTimeout = window.clearTimeout.bind(window);
  const realSetInterval = window.setInterval.bind(window);
  const realClearInterval = window.clearInterval.bind(window);
  const combinedLateness = window.__scratchworldLateness.combined; // lateness.js, loaded first
  delete window.__scratchworldLateness;
  // The VM's patches (vm-clock-patches.js, loaded first).
  const vmPatches = window.__scratchworldVmPatches.create(() => virtual, realPerformanceNow);
  delete window.__scratchworldVmPatches;
  const report = (error) => (window.reportError ? window.reportError(error) : realSetTimeout(() => { throw error; }, 0));

  // HTML timer rules: delays are whole milliseconds, and past 5 nested levels at least 4 ms.
  const NESTING_CLAMP_LEVEL = 5;
  const NESTED_MIN_DELAY_MS = 4;

  let virtual = false;
  let offsetMs = 0; // virtual time skipped so far: the clock stays monotonic after an evaluation
  let virtualNowMs = 0; // the clock while virtual
  let nextId = 1;
  let nextSeq = 1;
  let nesting = 0; // nesting level of the timer whose callback is running
  let firedVirtual = 0;
  let evaluating = false; // timers created meanwhile belong to an evaluation (see drainEvaluation)
  let steppedRuntime = null; // the VM's runtime, whose step interval sets the frame phase
  let draining = null; // {resolve, firings, untilMs} while drainEvaluation runs
  // Virtual mode: timers due later than this wait. Infinity while an evaluation runs; an episode's
  // page holds it at the present (time stands still while the agent thinks) and moves it in `advance`.
  let horizonMs = Infinity;
  let advancing = null; // {resolve} while `advance` runs
  let lateness = null; // (timer) => ms a repeating timer fires late, while a perturbed evaluation runs virtually
  const timers = new Map(); // id -> {id, seq, due, delay, repeat, nesting, fromEvaluation, callback, args, backing}

  function now() {
    return virtual ? virtualNowMs : realPerformanceNow() + offsetMs;
  }

  function dateNow() {
    if (!virtual && offsetMs === 0) return RealDate.now();
    return Math.floor(performance.timeOrigin + now());
  }

  function toCallback(handler) {
    if (typeof handler === 'function') return handler;
    const code = String(handler);
    return () => (0, eval)(code); // eslint-disable-line no-eval
  }

  function run(timer) {
    const outer = nesting;
    nesting = timer.nesting;
    try {
      timer.callback.apply(window, timer.args);
    } catch (error) {
      report(error);
    } finally {
      nesting = outer;
    }
  }

  // Real mode: the native timer decides when; the table keeps the due time for a switch to virtual.
  function arm(timer, delay) {
    if (timer.repeat && delay === timer.delay) {
      timer.backing = {interval: realSetInterval(() => fireReal(timer), delay)};
    } else {
      timer.backing = {timeout: realSetTimeout(() => fireReal(timer), delay)};
    }
  }

  function disarm(timer) {
    if (!timer.backing) return;
    if (timer.backing.interval !== undefined) realClearInterval(timer.backing.interval);
    else realClearTimeout(timer.backing.timeout);
    timer.backing = null;
  }

  function fireReal(timer) {
    if (timers.get(timer.id) !== timer) return;
    if (timer.repeat) {
      timer.due = now() + timer.delay;
      timer.nesting += 1;
      if (timer.backing && timer.backing.timeout !== undefined) arm(timer, timer.delay); // first run after a switch
    } else {
      timers.delete(timer.id);
      timer.backing = null;
    }
    runCounted(timer);
  }

  // ---- Frame work (the calibrated lateness model, and the frame trace of `benchmarks/frame_lateness.py`) ----

  let frameTrace = null; // [[clock ms, real ms, blocks, redraw 0/1, real ms the frame took], ...] while traced

  // Runs a timer; for the VM's frame timer, returns the work its frame did, {blocks, redraw}, else null.
  function runCounted(timer) {
    const frame = steppedRuntime !== null && steppedRuntime._steppingInterval === timer.id;
    const startedMs = now();
    const startedRealMs = realPerformanceNow();
    const before = vmPatches.blocksRun();
    run(timer);
    if (!frame) return null;
    const work = {blocks: vmPatches.blocksRun() - before, redraw: steppedRuntime.redrawRequested ? 1 : 0};
    if (frameTrace !== null && frameTrace.length < MAX_TRACED_FRAMES) {
      frameTrace.push([startedMs, startedRealMs, work.blocks, work.redraw, realPerformanceNow() - startedRealMs]);
    }
    return work;
  }

  const MAX_TRACED_FRAMES = 100000;

  /** Start recording every VM frame (both clocks); `takeFrameTrace` returns and stops the recording. */
  function traceFrames() {
    frameTrace = [];
  }

  function takeFrameTrace() {
    const trace = frameTrace;
    frameTrace = null;
    return trace;
  }

  // Virtual mode: one timer per task, the earliest first, ties in creation order.
  const channel = new MessageChannel();
  let pumpPending = false;

  function schedulePump() {
    if (virtual && !pumpPending && timers.size > 0) {
      pumpPending = true;
      channel.port2.postMessage(null);
    }
  }

  channel.port1.onmessage = () => {
    pumpPending = false;
    if (!virtual || (draining && drained())) return;
    let next = null;
    for (const timer of timers.values()) {
      if (draining && !timer.fromEvaluation) continue; // between evaluations only their leftovers fire
      if (next === null || timer.due < next.due || (timer.due === next.due && timer.seq < next.seq)) next = timer;
    }
    if (next === null || next.due > horizonMs) {
      endAdvance();
      return;
    }
    if (next.due > virtualNowMs) virtualNowMs = next.due;
    if (next.repeat) {
      next.nesting += 1;
      if (next.nesting > NESTING_CLAMP_LEVEL && next.delay < NESTED_MIN_DELAY_MS) next.delay = NESTED_MIN_DELAY_MS;
      next.due = virtualNowMs + next.delay;
      next.seq = nextSeq++;
    } else {
      timers.delete(next.id);
    }
    firedVirtual += 1;
    if (draining) draining.firings += 1;
    const work = runCounted(next);
    // Lateness comes after the run: a work-based model reads what the frame did (time stood still meanwhile).
    if (next.repeat && lateness && timers.get(next.id) === next) next.due += lateness(next, work);
    schedulePump();
  };

  function addTimer(handler, delay, args, repeat) {
    let ms = Math.trunc(Number(delay)) || 0;
    if (ms < 0) ms = 0;
    const level = nesting + 1;
    if (level > NESTING_CLAMP_LEVEL && ms < NESTED_MIN_DELAY_MS) ms = NESTED_MIN_DELAY_MS;
    const timer = {
      id: nextId++, seq: nextSeq++, due: now() + ms, delay: ms, repeat: repeat, nesting: level,
      fromEvaluation: evaluating, callback: toCallback(handler), args: args, backing: null,
    };
    timers.set(timer.id, timer);
    if (virtual) schedulePump();
    else arm(timer, ms);
    return timer.id;
  }

  function clearTimer(id) {
    const timer = timers.get(Number(id));
    if (!timer) return;
    disarm(timer);
    timers.delete(timer.id);
  }

  function VirtualDate(...args) {
    if (!new.target) return new RealDate(dateNow()).toString();
    return Reflect.construct(RealDate, args.length === 0 ? [dateNow()] : args, new.target);
  }
  VirtualDate.prototype = RealDate.prototype;
  VirtualDate.now = dateNow;
  VirtualDate.parse = RealDate.parse;
  VirtualDate.UTC = RealDate.UTC;
  Object.defineProperty(VirtualDate, 'name', {value: 'Date'});

  window.Date = VirtualDate;
  Object.defineProperty(performance, 'now', {value: now, writable: true, configurable: true});
  window.setTimeout = (handler, delay, ...args) => addTimer(handler, delay, args, false);
  window.setInterval = (handler, delay, ...args) => addTimer(handler, delay, args, true);
  window.clearTimeout = clearTimer;
  window.clearInterval = clearTimer;

  function frameTimer() {
    return steppedRuntime ? timers.get(steppedRuntime._steppingInterval) || null : null;
  }

  /**
   * Start virtual time at the current clock reading (an evaluation is about to run). `phaseMs`: the
   * VM's next frame comes that long after the start (default 0: right at it); `lateness`: the model
   * and parameters of repeating timers' lateness until `stopVirtual` (default none); `frameTiming`:
   * a second model for the frame loop (the calibrated one), added to the first.
   */
  function startVirtual(options = {}) {
    if (virtual) throw new Error('the clock is already virtual');
    const late = combinedLateness([options.lateness, options.frameTiming]);
    virtualNowMs = now();
    // Start on the VM's next frame, not somewhere inside the current one: the script then meets
    // the VM at the same phase on every run, so the same project gives the same times to the ms.
    const frame = frameTimer();
    if (frame && frame.due > virtualNowMs) virtualNowMs = frame.due;
    if (frame && options.phaseMs > 0) frame.due = virtualNowMs + options.phaseMs;
    for (const timer of timers.values()) disarm(timer);
    virtual = true;
    lateness = late;
    horizonMs = Infinity;
    schedulePump();
  }

  /** Virtual time that stands still until `advance` moves it (an agent's page between actions). */
  function pauseVirtual() {
    startVirtual();
    horizonMs = virtualNowMs;
  }

  /** Let `ms` of virtual time pass, firing the timers due meanwhile; resolves when it has. */
  function advance(ms) {
    if (!virtual || horizonMs === Infinity) throw new Error('the clock is not paused');
    if (advancing) throw new Error('the clock is already advancing');
    horizonMs = virtualNowMs + ms;
    return new Promise((resolve) => {
      advancing = {resolve};
      if (timers.size === 0) endAdvance();
      else schedulePump();
    });
  }

  // Nothing more is due before the horizon: the clock reaches it and holds there.
  function endAdvance() {
    if (!advancing || horizonMs === Infinity) return;
    if (horizonMs > virtualNowMs) virtualNowMs = horizonMs;
    const finish = advancing.resolve;
    advancing = null;
    finish();
  }

  /** Back to real time, keeping the clock monotonic: time goes on at real speed from here. */
  function stopVirtual() {
    if (!virtual) return;
    endAdvance();
    horizonMs = Infinity;
    virtual = false;
    lateness = null;
    offsetMs = virtualNowMs - realPerformanceNow();
    const at = now();
    for (const timer of timers.values()) arm(timer, Math.max(0, Math.ceil(timer.due - at)));
  }

  // ---- Between evaluations ----------------------------------------------------------------------

  /** Timers created from now until the evaluation is drained (its own and the page's) belong to it. */
  function beginEvaluation() {
    evaluating = true;
  }

  const DRAIN_MAX_FIRINGS = 20000;
  const DRAIN_MAX_MS = 10 * 60 * 1000;

  function evaluationTimers() {
    return [...timers.values()].filter((timer) => timer.fromEvaluation);
  }

  // Checked at the start of a pump task, so that promise callbacks of the last firing have run
  // (and created their timers) by then.
  function drained() {
    const left = evaluationTimers();
    const done = left.every((timer) => timer.repeat) || draining.firings > DRAIN_MAX_FIRINGS ||
      virtualNowMs > draining.untilMs;
    if (done) {
      const finish = draining.resolve;
      draining = null;
      finish(left);
    }
    return done;
  }

  /**
   * Let the timeouts an evaluation left behind (a race's losing timer, a poll still pending) fire
   * now, in virtual time and ahead of every other timer, as they would have later; then back to
   * real time at the real clock, so the next project starts where a fresh page would. Resolves to
   * what is left: intervals, and timeouts that keep rescheduling themselves, which a reused page
   * must not carry over.
   */
  async function drainEvaluation() {
    let left = evaluationTimers();
    if (left.some((timer) => !timer.repeat)) {
      const wasVirtual = virtual;
      if (!wasVirtual) startVirtual();
      left = await new Promise((resolve) => {
        draining = {resolve, firings: 0, untilMs: virtualNowMs + DRAIN_MAX_MS};
        schedulePump();
      });
      if (!wasVirtual) stopVirtual();
    }
    evaluating = false;
    resync();
    return left.map((timer) => `${timer.repeat ? 'an interval' : 'a timeout'} of ${timer.delay} ms`);
  }

  /** Real mode: drop the offset the virtual runs left, so the clocks read real time again. */
  function resync() {
    if (virtual || offsetMs === 0) return;
    for (const timer of timers.values()) timer.due -= offsetMs;
    offsetMs = 0;
  }

  function status() {
    return {
      mode: virtual ? 'virtual' : 'real',
      paused: virtual && horizonMs !== Infinity && !advancing,
      now: now(),
      realNow: realPerformanceNow(),
      dateNow: VirtualDate.now(),
      realDateNow: RealDate.now(),
      offsetMs: offsetMs,
      pendingTimers: timers.size,
      firedVirtual: firedVirtual,
      sideEffects: vmPatches.sideEffects(),
      blocksRun: vmPatches.blocksRun(),
      tracing: frameTrace !== null,
    };
  }

  function attachVm(vm) {
    steppedRuntime = vm.runtime;
    vmPatches.install(vm);
  }

  window.__scratchworldClock = Object.freeze({
    startVirtual, stopVirtual, pauseVirtual, advance, status, attachVm, now, beginEvaluation, drainEvaluation,
    traceFrames, takeFrameTrace,
    realNow: realPerformanceNow,
    realSleep: (ms) => new Promise((resolve) => realSetTimeout(resolve, ms)),
  });
})();
