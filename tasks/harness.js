/*
 * Harness: the helper module of the scratchworld_dist task suite.
 *
 * The evaluator installs its exports as the global `Harness` before a task's evaluate.js runs.
 * Scripts use it to drive a live Scratch VM (green flag, keys, clicks, answers to "ask" blocks,
 * the mouse) and to observe it (sprites, variables, speech, broadcasts, clones), then report with
 * `Harness.runTests`, which returns the benchmark's report shape.
 *
 * Lookups are exact: a sprite or variable is found by its exact name, never by substring, so a
 * project cannot pass by accident because of a similarly named sprite.
 */
'use strict';

const STAGE_WIDTH = 480;
const STAGE_HEIGHT = 360;

// Bumped by runTests at every test, so that the code of a test that timed out (and keeps
// running in the background, as JavaScript cannot cancel it) stops at its next wait instead
// of touching the VM while the next test runs.
let currentTest = 0;

/** Sleeps `ms`; throws when the test that called it has been abandoned meanwhile. */
async function wait(ms) {
  const caller = currentTest;
  await new Promise(resolve => setTimeout(resolve, ms));
  if (caller !== currentTest) throw new Error('abandoned: the test timed out and a later test is running');
}

/** Polls `predicate` until it is truthy; resolves to whether it became so in time. */
async function waitUntil(predicate, {timeoutMs = 3000, intervalMs = 20} = {}) {
  const deadline = Date.now() + timeoutMs;
  while (Date.now() < deadline) {
    if (predicate()) return true;
    await wait(intervalMs);
  }
  return !!predicate();
}

/** The original (non-clone) sprite called exactly `name`; throws when there is none. */
function sprite(vm, name) {
  const target = vm.runtime.targets.find(t => t.isOriginal && !t.isStage && t.getName() === name);
  if (!target) {
    const names = vm.runtime.targets.filter(t => t.isOriginal && !t.isStage).map(t => t.getName());
    throw new Error(`no sprite named "${name}" (sprites: ${names.join(', ') || 'none'})`);
  }
  return target;
}

function stage(vm) {
  return vm.runtime.getTargetForStage();
}

/** Live clones of a sprite. */
function clones(vm, name) {
  return vm.runtime.targets.filter(t => !t.isOriginal && t.sprite && t.sprite.name === name);
}

/**
 * A variable (type '' ) or list (type 'list') by exact name, looked up in the sprite first
 * (when `spriteName` is given) and then on the stage; null when missing.
 */
function findVariable(vm, name, {spriteName = null, type = ''} = {}) {
  const owners = spriteName ? [sprite(vm, spriteName), stage(vm)] : [stage(vm)];
  for (const owner of owners) {
    const found = Object.values(owner.variables).find(v => v.name === name && v.type === type);
    if (found) return found;
  }
  return null;
}

/** The value of a variable, or undefined when it does not exist. */
function valueOf(vm, name, options = {}) {
  const found = findVariable(vm, name, options);
  return found ? found.value : undefined;
}

/** Stops everything and clicks the green flag, as a person would before testing. */
async function start(vm, settleMs = 100) {
  vm.runtime.stopAll();
  vm.greenFlag();
  await wait(settleMs);
}

/**
 * Calls `onFrame()` after every VM step (one frame, ~30 per second), which is far more reliable
 * for watching motion than polling on timers; `stop()` restores the VM.
 */
function sampleFrames(vm, onFrame) {
  const runtime = vm.runtime;
  const original = runtime._step;
  runtime._step = function () {
    const result = original.apply(this, arguments);
    onFrame();
    return result;
  };
  return {stop: () => { runtime._step = original; }};
}

/**
 * Runs `fn` with `Math.random` returning `value` (0 <= value < 1), then restores it: "pick random
 * 1 to 100" gives 1 under 0 and 100 under 0.999999, so a test can check both ends of a range.
 */
async function withRandom(value, fn) {
  const original = Math.random;
  Math.random = () => value;
  try {
    return await fn();
  } finally {
    Math.random = original;
  }
}

/** Records what sprites say or think: `texts(spriteName?)` lists them in order. */
function recordSpeech(vm) {
  const events = [];
  const listener = (target, type, text) => {
    if (text === '' || text === null || text === undefined) return;
    events.push({sprite: target.sprite ? target.sprite.name : target.getName(), type, text: String(text)});
  };
  vm.runtime.on('SAY', listener);
  return {
    events,
    texts: (name = null) => events.filter(e => name === null || e.sprite === name).map(e => e.text),
    stop: () => vm.runtime.removeListener('SAY', listener),
  };
}

/**
 * Records every change of `spriteName`'s speech bubble, cleared ones included (text ''), with its
 * time (ms since recording began) and `snapshot()` at that moment: `changes` in order, and
 * `shown(texts)`: how long each bubble showing one of `texts` stayed (until the bubble next
 * changed; null if it had not yet), `[{text, ms, value}]`.
 */
function recordBubbles(vm, spriteName, snapshot = () => null) {
  const changes = [];
  const start = Date.now(); // times are kept relative so a test's details never carry the wall date
  const listener = (target, type, text) => {
    if (!target.sprite || target.sprite.name !== spriteName) return;
    changes.push({text: text === null || text === undefined ? '' : String(text).trim(), t: Date.now() - start, value: snapshot()});
  };
  vm.runtime.on('SAY', listener);
  return {
    changes,
    shown: (texts) => changes.flatMap((c, i) => (texts.includes(c.text)
      ? [{text: c.text, ms: i + 1 < changes.length ? changes[i + 1].t - c.t : null, value: c.value}] : [])),
    stop: () => vm.runtime.removeListener('SAY', listener),
  };
}

/** Records broadcast messages as they start their receivers: `names()` lists them in order. */
function recordBroadcasts(vm) {
  const names = [];
  const runtime = vm.runtime;
  const original = runtime.startHats;
  runtime.startHats = function (opcode, matchFields, target) {
    if (opcode === 'event_whenbroadcastreceived' && matchFields && matchFields.BROADCAST_OPTION) {
      names.push(String(matchFields.BROADCAST_OPTION));
    }
    return original.apply(this, arguments);
  };
  return {names: () => names.slice(), stop: () => { runtime.startHats = original; }};
}

/**
 * Answers "ask and wait" prompts in order. A sprite shows its question in a speech bubble (the
 * VM emits it as SAY and the prompt as an empty QUESTION); the stage's question arrives as text.
 * `answered` counts answers given; `speechMark` is the speech count when the last one was given;
 * `asked` lists the questions' texts ('' for a question asked with no text).
 */
function answerQuestions(vm, answers, speech = null) {
  const queue = answers.map(String);
  const state = {prompts: 0, answered: 0, speechMark: null, asked: []};
  let lastSaid = '';
  const onSay = (target, type, text) => { lastSaid = text === null || text === undefined ? '' : String(text); };
  const listener = (question) => {
    if (question === null || question === undefined) return; // the prompt was cleared
    state.prompts += 1;
    state.asked.push(question !== '' ? String(question) : lastSaid); // a sprite's question is in its bubble
    if (!queue.length) return;
    const answer = queue.shift();
    setTimeout(() => {
      state.answered += 1;
      if (!queue.length && speech) state.speechMark = speech.events.length;
      vm.runtime.emit('ANSWER', answer);
    }, 30);
  };
  vm.runtime.on('SAY', onSay);
  vm.runtime.on('QUESTION', listener);
  state.stop = () => {
    vm.runtime.removeListener('QUESTION', listener);
    vm.runtime.removeListener('SAY', onSay);
  };
  return state;
}

/**
 * Clicks the green flag, answers each prompt in turn and resolves with what `spriteName` says
 * after the last answer: `{prompts, replies, asked}`. Waits at most `timeoutMs` for the first reply.
 */
async function askAndListen(vm, spriteName, answers, {timeoutMs = 4000, settleMs = 200} = {}) {
  const speech = recordSpeech(vm);
  const questions = answerQuestions(vm, answers, speech);
  const replies = () => questions.speechMark === null ? [] :
    speech.events.slice(questions.speechMark).filter(e => e.sprite === spriteName).map(e => e.text);
  try {
    await start(vm, 0);
    await waitUntil(() => replies().length > 0, {timeoutMs});
    await wait(settleMs); // a second, later reply would make the answer ambiguous
    return {prompts: questions.prompts, replies: replies(), asked: questions.asked.slice()};
  } finally {
    speech.stop();
    questions.stop();
  }
}

/** Holds a key (Scratch names: 'space', 'left arrow', 'a', ...) for `holdMs`. */
async function pressKey(vm, key, holdMs = 100) {
  const browserKey = {
    'space': ' ', 'left arrow': 'ArrowLeft', 'right arrow': 'ArrowRight',
    'up arrow': 'ArrowUp', 'down arrow': 'ArrowDown', 'enter': 'Enter',
  }[key] || key;
  vm.postIOData('keyboard', {key: browserKey, isDown: true});
  await wait(holdMs);
  vm.postIOData('keyboard', {key: browserKey, isDown: false});
}

/** Clicks a sprite: starts its "when this sprite clicked" scripts. */
function clickSprite(vm, name) {
  return vm.runtime.startHats('event_whenthisspriteclicked', null, sprite(vm, name));
}

/** Moves the mouse to stage coordinates (x right, y up, origin at the centre). */
function moveMouse(vm, x, y, isDown = false) {
  vm.postIOData('mouse', {
    x: x + STAGE_WIDTH / 2, y: STAGE_HEIGHT / 2 - y,
    canvasWidth: STAGE_WIDTH, canvasHeight: STAGE_HEIGHT, isDown,
  });
}

/**
 * Runs tests one after another and returns the benchmark's report. Each test is
 * `{name, timeoutMs, run: async () => ({passed, meta?})}`; everything is stopped before and
 * after each test, a test that throws or times out fails with the reason (and the abandoned
 * test's code stops at its next `wait`/`waitUntil`).
 */
async function runTests(vm, tests) {
  const details = [];
  for (const test of tests) {
    currentTest += 1;
    const started = Date.now();
    let timer = null;
    const detail = {name: test.name, passed: false, timeout: false, duration_ms: 0, error: null, meta: null};
    vm.runtime.stopAll();
    try {
      const limit = new Promise((resolve) => {
        timer = setTimeout(() => resolve({timedOut: true}), test.timeoutMs || 10000);
      });
      const outcome = await Promise.race([Promise.resolve().then(test.run), limit]);
      if (outcome && outcome.timedOut) {
        detail.timeout = true;
        detail.error = `timed out after ${test.timeoutMs || 10000} ms`;
      } else {
        detail.passed = !!(outcome && outcome.passed);
        detail.meta = outcome && outcome.meta !== undefined ? outcome.meta : null;
      }
    } catch (error) {
      detail.error = error && error.message ? error.message : String(error);
    } finally {
      clearTimeout(timer);
      vm.runtime.stopAll();
    }
    detail.duration_ms = Date.now() - started;
    details.push(detail);
  }
  const passed = details.filter(d => d.passed).length;
  return {
    success: passed === details.length,
    passed_tests: passed,
    total_tests: details.length,
    partial_success_rate: details.length ? passed / details.length : 0,
    details,
  };
}

module.exports = {
  STAGE_WIDTH, STAGE_HEIGHT,
  wait, waitUntil, sprite, stage, clones, findVariable, valueOf, start,
  sampleFrames, withRandom, recordSpeech, recordBubbles, recordBroadcasts, answerQuestions, askAndListen, pressKey, clickSprite, moveMouse, runTests,
};
