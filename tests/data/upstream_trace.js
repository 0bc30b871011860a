// A generic trace of what an (upstream) project does after the green flag, for comparing clocks.
//
// The run is made deterministic where the page would otherwise differ between two runs: Math.random
// is a seeded generator while the VM steps (and only then, so the GUI's own calls cannot shift the
// sequence), the mouse sits at a fixed point, and every input (keys, clicks, mouse moves, answers to
// "ask") is given at the start of a frame counted from the green flag, not at a clock time. What is
// left to the clock is exactly what the project asks of it: waits, glides, timed says, sounds.
//
// config: {ms: page time to run for at least, frames: frames to run for at least (by default as many
//          as fit in `ms`, so that a real run whose frames come late still covers them), seed,
//          mouse: [x, y] (Scratch coordinates),
//          answers: texts given in turn to each question, answerAfter: frames before answering,
//          inputs: [{frame, key, down} | {frame, click: sprite} | {frame, mouse: [x, y], down}]}
//
// Returns one test whose meta holds the trace: `events`, each [ms, frame, kind, who, value] in the
// order they happened, and `frames`: the page time of every frame and, after it, each sprite's position
// with the sums of its clones' positions ([x, y, clones' x, clones' y]).
'use strict';

const KEYS = {'space': ' ', 'up arrow': 'ArrowUp', 'down arrow': 'ArrowDown', 'left arrow': 'ArrowLeft',
  'right arrow': 'ArrowRight', 'enter': 'Enter'};

function seeded(seed) { // mulberry32: small, fast, and the same sequence in every browser
  let state = seed >>> 0;
  return () => {
    state = (state + 0x6d2b79f5) >>> 0;
    let t = state;
    t = Math.imul(t ^ (t >>> 15), t | 1);
    t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}

module.exports = async (vm, config) => {
  const runtime = vm.runtime;
  const spanMs = Number(config.ms) || 3000;
  const spanFrames = Number(config.frames) || Math.floor(spanMs / 33) - 1;
  const random = seeded(Number(config.seed) || 20240601);
  const answers = config.answers || ['7'];
  const answerAfter = Number(config.answerAfter) || 3;
  const inputs = [...(config.inputs || [])].sort((a, b) => a.frame - b.frame);
  const [mouseX, mouseY] = config.mouse || [40, 30];

  const originals = () => runtime.targets.filter((t) => t.isOriginal);
  const sprites = originals().filter((t) => !t.isStage);
  const byName = (name) => sprites.find((t) => t.getName() === name);
  const toClient = (x, y) => ({x: x + 240, y: 180 - y, canvasWidth: 480, canvasHeight: 360});

  let started = performance.now();
  let frame = 0;
  let running = true;
  const events = [];
  const log = (kind, who, value) => {
    if (running) events.push([Math.round((performance.now() - started) * 10) / 10, frame, kind, who, value]);
  };
  const nameOf = (target) => (target.isOriginal ? target.getName() : `${target.getName()} (clone)`);

  // What the project says, asks, broadcasts, sounds and whether it runs: logged as it happens.
  const bubbles = new Map(); // target -> what its bubble shows
  const created = {}; // sprite name -> clones made so far
  let pendingAnswer = null; // the frame the question asked gets its answer on
  let answered = 0;
  const listeners = {
    SAY: (target, type, text) => { // a bubble said again unchanged (a `say` in a loop) is no event
      const said = `${type}: ${text}`;
      if (bubbles.get(target) !== said) log('say', nameOf(target), said);
      bubbles.set(target, said);
    },
    QUESTION: (question) => {
      if (question === null) {
        pendingAnswer = null;
        return;
      }
      log('ask', '', String(question));
      pendingAnswer = frame + answerAfter;
    },
    PROJECT_RUN_START: () => log('run', '', 'start'),
    PROJECT_RUN_STOP: () => log('run', '', 'stop'),
    targetWasCreated: (clone) => {
      created[clone.getName()] = (created[clone.getName()] || 0) + 1;
    },
  };
  for (const [event, listener] of Object.entries(listeners)) runtime.on(event, listener);

  const startHats = runtime.startHats;
  runtime.startHats = function (opcode, fields) {
    if (opcode === 'event_whenbroadcastreceived' && fields) log('broadcast', '', String(fields.BROADCAST_OPTION));
    return startHats.apply(this, arguments);
  };
  const banks = new Map(); // sound bank -> its own playSound before ours (normally none: a prototype method)
  for (const target of originals()) {
    const bank = target.sprite.soundBank;
    if (!bank || banks.has(bank)) continue;
    banks.set(bank, Object.prototype.hasOwnProperty.call(bank, 'playSound') ? bank.playSound : null);
    const play = bank.playSound;
    bank.playSound = function (playing, soundId) {
      const sound = playing.sprite.sounds.find((s) => s.soundId === soundId);
      const name = sound ? sound.name : soundId;
      log('sound', nameOf(playing), `start: ${name}`);
      const ended = play.apply(this, arguments);
      if (ended && ended.then) ended.then(() => log('sound', nameOf(playing), `end: ${name}`));
      return ended;
    };
  }

  // State read after every frame: a change is logged with the frame it showed up in.
  const state = new Map();
  const changed = (kind, who, value) => {
    const key = `${kind}\u0000${who}`;
    if (state.has(key) && state.get(key) === value) return;
    if (state.has(key)) log(kind, who, value);
    state.set(key, value);
  };
  const frames = {t: [], pos: Object.fromEntries(sprites.map((t) => [t.getName(), []]))};
  function sample() {
    for (const target of originals()) {
      const who = target.getName();
      for (const variable of Object.values(target.variables)) {
        if (variable.type === 'list') changed('list', `${who}.${variable.name}`, variable.value.length);
        else if (variable.type === '') changed('var', `${who}.${variable.name}`, String(variable.value));
      }
      changed(target.isStage ? 'backdrop' : 'costume', who, target.getCostumes()[target.currentCostume].name);
      if (target.isStage) continue;
      changed('visible', who, target.visible);
      const clones = runtime.targets.filter((t) => !t.isOriginal && t.sprite === target.sprite);
      changed('clones', who, `${clones.length} live, ${created[who] || 0} made`);
      const sum = (axis) => clones.reduce((total, clone) => total + clone[axis], 0);
      frames.pos[who].push([target.x, target.y, sum('x'), sum('y')].map((v) => Math.round(v * 100) / 100));
    }
    frames.t.push(Math.round((performance.now() - started) * 10) / 10);
  }

  function give(input) {
    if (input.key !== undefined) {
      vm.postIOData('keyboard', {key: KEYS[input.key] || input.key, isDown: input.down !== false});
    } else if (input.click !== undefined) {
      runtime.startHats('event_whenthisspriteclicked', null, byName(input.click));
    } else if (input.mouse !== undefined) {
      vm.postIOData('mouse', {...toClient(...input.mouse), isDown: Boolean(input.down)});
    }
  }

  const step = runtime._step;
  const realRandom = Math.random;
  runtime._step = function () {
    frame += 1;
    while (inputs.length > 0 && inputs[0].frame <= frame) give(inputs.shift());
    if (pendingAnswer !== null && frame >= pendingAnswer) {
      pendingAnswer = null;
      runtime.emit('ANSWER', String(answers[answered++ % answers.length]));
    }
    Math.random = random;
    try {
      return step.apply(this, arguments);
    } finally {
      Math.random = realRandom;
      if (running) sample();
    }
  };

  try {
    vm.postIOData('mouse', {...toClient(mouseX, mouseY), isDown: false});
    vm.greenFlag();
    started = performance.now();
    sample(); // the state right after the green flag: the baseline changes are logged against
    frames.t.length = 0;
    for (const track of Object.values(frames.pos)) track.length = 0;
    await new Promise((resolve) => setTimeout(resolve, spanMs));
    while (frame < spanFrames) await new Promise((resolve) => setTimeout(resolve, 5));
    running = false;
  } finally {
    running = false;
    runtime._step = step;
    runtime.startHats = startHats;
    for (const [bank, own] of banks) {
      if (own) bank.playSound = own;
      else delete bank.playSound;
    }
    for (const [event, listener] of Object.entries(listeners)) runtime.removeListener(event, listener);
    runtime.stopAll();
  }
  const end = {ms: Math.round((performance.now() - started) * 10) / 10, frame};
  return {details: [{name: 'trace', passed: events.length > 0, meta: {events, frames, end}}]};
};
