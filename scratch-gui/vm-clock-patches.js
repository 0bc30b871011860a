/*
 * The clock's patches of the VM (installed by clock.js's `attachVm`): a fake clock alone would hang or
 * slow the VM, which also measures work on the clock.
 * - Its per-frame work budget and its threads' warp timers use the real clock; in virtual mode a frame's
 *   work also stops after a pass over the threads in which no block with a side effect ran, since every
 *   further pass would repeat it exactly (time being frozen).
 * - "Play sound until done" ends after the sound's length in virtual time (the audio clock is no timer).
 * - Every block call is counted (`blocksRun`, one increment, no clock read): the work a frame did, for
 *   the calibrated lateness model and the frame trace.
 * clock.js takes `create` from `window.__scratchworldVmPatches` (and deletes it); it is loaded just before.
 */
(function () {
  'use strict';

  // `isVirtual()`: whether the page clock is virtual now; `realNow()`: the real performance.now.
  function create(isVirtual, realNow) {
    let blocksRun = 0; // block functions called by the VM (reporters included)

    const REAL_CLOCK = Object.freeze({now: realNow});

    // Blocks that only read state or steer control flow: a pass running nothing else changed nothing,
    // and, time being frozen, the next pass would do exactly the same. Everything else counts as a
    // side effect, on the safe side: procedure calls, repeat counters, pick random, extension blocks.
    const PURE = new Set([
      'motion_xposition', 'motion_yposition', 'motion_direction',
      'looks_costumenumbername', 'looks_backdropnumbername', 'looks_size', 'sound_volume',
      'control_forever', 'control_if', 'control_if_else', 'control_repeat_until', 'control_while',
      'control_wait_until', 'control_all_at_once', 'control_get_counter',
      'sensing_touchingobject', 'sensing_touchingcolor', 'sensing_coloristouchingcolor', 'sensing_distanceto',
      'sensing_timer', 'sensing_keypressed', 'sensing_mousedown', 'sensing_mousex', 'sensing_mousey',
      'sensing_loudness', 'sensing_loud', 'sensing_of', 'sensing_current', 'sensing_dayssince2000',
      'sensing_username', 'sensing_userid', 'sensing_answer',
      'data_variable', 'data_listcontents', 'data_itemoflist', 'data_itemnumoflist', 'data_lengthoflist',
      'data_listcontainsitem', 'argument_reporter_string_number', 'argument_reporter_boolean',
      'event_whengreaterthan', 'event_whentouchingobject',
    ]);
    // Blocks that poll across frames: only their first call (fresh stack frame) does something.
    const POLLING = new Set([
      'control_wait', 'motion_glidesecstoxy', 'motion_glideto', 'event_broadcastandwait',
      'looks_switchbackdroptoandwait',
    ]);
    let sideEffects = 0;

    function isPure(opcode) {
      return PURE.has(opcode) || (opcode.startsWith('operator_') && opcode !== 'operator_random');
    }

    function countingBlock(opcode, fn) {
      if (opcode === 'data_setvariableto') { // setting a variable to the value it has changes nothing
        return function (args, util) {
          const variable = util.target.lookupOrCreateVariable(args.VARIABLE.id, args.VARIABLE.name);
          const before = variable.value;
          const result = fn.call(this, args, util);
          if (variable.value !== before) sideEffects += 1;
          return result;
        };
      }
      if (POLLING.has(opcode)) {
        return function (args, util) {
          const ctx = util.thread.peekStackFrame().executionContext;
          if (!ctx || Object.keys(ctx).length === 0) sideEffects += 1;
          return fn.call(this, args, util);
        };
      }
      return function (args, util) {
        sideEffects += 1;
        if (opcode.startsWith('sound_') && util && util.target) patchSoundPlayers(util.target);
        return fn.call(this, args, util);
      };
    }

    // Every block call counts as work (the calibrated lateness model): one increment, no clock read.
    function countingWork(fn) {
      return function (args, util) {
        blocksRun += 1;
        return fn.call(this, args, util);
      };
    }

    // The frame's work budget on the real clock; in virtual mode also "stop after an idle pass".
    function sequencerTimer(runtime) {
      let started = 0;
      let passes = 0;
      let mark = '';
      return {
        nowObj: REAL_CLOCK,
        time: realNow,
        start() {
          started = realNow();
          passes = 0;
        },
        timeElapsed() {
          const elapsed = realNow() - started;
          if (isVirtual()) {
            const current = `${sideEffects}/${runtime.threads.length}`;
            if (passes > 0 && current === mark) return Infinity;
            mark = current;
          }
          passes += 1;
          return elapsed;
        },
      };
    }

    // Threads get their warp timer ("run without screen refresh") on the real clock: frozen, it would
    // never run out and a warp loop with a wait inside would spin forever.
    function patchThreads(thread) {
      const proto = Object.getPrototypeOf(thread);
      if (Object.prototype.hasOwnProperty.call(proto, 'warpTimer')) return;
      const key = Symbol('warpTimer');
      Object.defineProperty(proto, 'warpTimer', {
        configurable: true,
        get() { return this[key] || null; },
        set(timer) {
          if (timer) timer.nowObj = REAL_CLOCK;
          this[key] = timer;
        },
      });
      const own = thread.warpTimer;
      delete thread.warpTimer;
      thread.warpTimer = own;
    }

    // Sound players: a sound started in virtual mode ends after its length in virtual time; its real
    // end (an audio event, on the audio clock) is ignored. Stops and restarts stay immediate. Players
    // bind handleEvent at construction, so the hook is onEnded, which handleEvent looks up each time.
    function patchSoundPlayers(target) {
      const bank = target.sprite && target.sprite.soundBank;
      const player = bank && Object.values(bank.soundPlayers || {})[0];
      if (!player) return;
      const proto = Object.getPrototypeOf(player);
      if (Object.prototype.hasOwnProperty.call(proto, '__scratchworldClock')) return;
      Object.defineProperty(proto, '__scratchworldClock', {value: true});
      const play = proto.play;
      const onEnded = proto.onEnded;
      proto.play = function () {
        const restarting = this.isStarting; // play() then only re-announces the sound already starting
        const result = play.apply(this, arguments);
        if (restarting && this.__virtualEnd) return result;
        this.__virtualEnd = null;
        if (isVirtual() && this.isPlaying && this.buffer) {
          const token = {source: this.outputNode};
          this.__virtualEnd = token;
          window.setTimeout(() => {
            if (this.__virtualEnd === token && this.isPlaying) onEnded.call(this);
          }, (1000 * this.buffer.duration) / (this.playbackRate || 1));
        }
        return result;
      };
      proto.onEnded = function () {
        const token = this.__virtualEnd; // the real end of a sound that ends in virtual time
        if (token && token.source === this.outputNode) return undefined;
        return onEnded.apply(this, arguments);
      };
    }

    function install(vm) {
      const runtime = vm.runtime;
      runtime.sequencer.timer = sequencerTimer(runtime);
      const pushThread = runtime._pushThread;
      runtime._pushThread = function () {
        const thread = pushThread.apply(this, arguments);
        if (thread) patchThreads(thread);
        return thread;
      };
      const getOpcodeFunction = runtime.getOpcodeFunction;
      const wrapped = new Map();
      runtime.getOpcodeFunction = function (opcode) {
        const fn = getOpcodeFunction.call(this, opcode);
        if (typeof fn !== 'function') return fn;
        const cached = wrapped.get(opcode);
        if (cached && cached.fn === fn) return cached.wrapper;
        const wrapper = countingWork(isPure(opcode) ? fn : countingBlock(opcode, fn));
        wrapped.set(opcode, {fn, wrapper});
        return wrapper;
      };
    }

    return Object.freeze({install, blocksRun: () => blocksRun, sideEffects: () => sideEffects});
  }

  window.__scratchworldVmPatches = Object.freeze({create});
})();
