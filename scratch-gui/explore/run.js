/*
 * An exploration of a program, independent of any task's tests (the grader audit, workers/kinds/audit): the
 * runner `explore`, which `evaluate` runs in place of a task's script (`runner: {name: 'explore', args}`),
 * under the evaluation's clock, seed and observable trace. Its arguments are a timeline:
 *
 *   {stimuli: [{atMs, kind, name, holdMs}], answers: [text], answerDelayMs, spanMs}
 *
 * Each stimulus (explore/stimuli.js) is done `atMs` after the run starts, in order; every question asked
 * meanwhile is answered from `answers`; the run ends `spanMs` after it started. In virtual time and with
 * a seeded Math.random (the evaluation's perturbation), a program explored twice is the same run twice.
 * It returns {answers: [given], answeredAt: [frame], applied: [{index, frame, found}], steps}: the answers
 * given in order and the trace frame each was given at, and the frame each stimulus was done at (the VM
 * steps before it; its effects show from the next frame on).
 */
scratchworldModule({name: 'explore/run', requires: ['explore/stimuli', 'trace/record'], create(ctx, stimuli, record) {
  'use strict';

  const MAX_STIMULI = 500;
  const MAX_SPAN_MS = 10 * 60 * 1000;
  const MAX_ANSWERS = 200;
  const MAX_ANSWER_CHARS = 1000;
  const MAX_DELAY_MS = 60 * 1000;

  const bad = (message) => new ctx.BridgeFailure('bad_request', `explore: ${message}`);
  const whole = (value, low, high) => Number.isInteger(value) && value >= low && value <= high;

  // The timeline, checked before anything runs (a failure names the first bad part).
  function checked(args) {
    const {stimuli: given, answers, answerDelayMs, spanMs} = args;
    if (!whole(spanMs, 1, MAX_SPAN_MS)) throw bad(`spanMs must be an integer from 1 to ${MAX_SPAN_MS}`);
    if (!whole(answerDelayMs, 0, MAX_DELAY_MS)) throw bad(`answerDelayMs must be an integer from 0 to ${MAX_DELAY_MS}`);
    if (!Array.isArray(answers) || answers.length > MAX_ANSWERS) throw bad(`answers must be a list of at most ${MAX_ANSWERS}`);
    for (const answer of answers) {
      if (typeof answer !== 'string' || answer.length > MAX_ANSWER_CHARS) {
        throw bad(`each answer must be a text of at most ${MAX_ANSWER_CHARS} characters`);
      }
    }
    if (!Array.isArray(given) || given.length > MAX_STIMULI) throw bad(`stimuli must be a list of at most ${MAX_STIMULI}`);
    let previous = 0;
    const timeline = given.map((stimulus, index) => {
      const where = `stimuli[${index}]`;
      if (!stimulus || !stimuli.KINDS.includes(stimulus.kind)) throw bad(`${where}.kind must be one of ${stimuli.KINDS.join(', ')}`);
      if (!whole(stimulus.atMs, previous, spanMs)) throw bad(`${where}.atMs must be an integer from ${previous} (the one before) to spanMs`);
      const holdMs = stimulus.holdMs == null ? 0 : stimulus.holdMs;
      if (!whole(holdMs, 0, MAX_DELAY_MS)) throw bad(`${where}.holdMs must be an integer from 0 to ${MAX_DELAY_MS}`);
      const name = stimulus.name == null ? '' : stimulus.name;
      if (typeof name !== 'string' || name.length > MAX_ANSWER_CHARS) throw bad(`${where}.name must be a short text`);
      if (stimulus.kind !== 'green_flag' && stimulus.kind !== 'stage_click' && name === '') throw bad(`${where} names nothing to act on`);
      previous = stimulus.atMs;
      return {atMs: stimulus.atMs, kind: stimulus.kind, name: name, holdMs: holdMs};
    });
    return {timeline, answers: answers.slice(), answerDelayMs, spanMs};
  }

  // Resolves at `when` on the page clock (virtual during an evaluation: it jumps there).
  const until = (when) => new Promise((resolve) => setTimeout(resolve, Math.max(0, when - Date.now())));

  ctx.addRunner('explore', (args) => {
    const plan = checked(args);
    return async (vm) => {
      const held = new Map();
      const applied = [];
      const answering = stimuli.answerer(vm, plan.answers, plan.answerDelayMs, record.frame);
      const started = Date.now();
      try {
        for (let index = 0; index < plan.timeline.length; index++) {
          const stimulus = plan.timeline[index];
          await until(started + stimulus.atMs);
          const frame = record.frame();
          applied.push({index, frame, found: stimuli.apply(vm, stimulus, held)});
        }
        await until(started + plan.spanMs);
      } finally {
        answering.stop();
        stimuli.releaseAll(vm, held);
      }
      return {answers: answering.given.slice(), answeredAt: answering.at.slice(), applied, steps: record.frame()};
    };
  });

  return {};
}});
