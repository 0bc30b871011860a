// extend/quiz_score: the base quiz (two questions, "Correct!"/"Wrong!" feedback) must keep
// working; the new `score` starts at 0, counts right answers and is announced as "Score: N".

// A number from a Scratch value; NaN for empty text, so '' never passes as 0.
const num = v => (typeof v === 'number' ? v : (typeof v === 'string' && v.trim() !== '' ? Number(v) : NaN));
const FEEDBACK = ['Correct!', 'Wrong!'];

// Green flag, answer both questions, and report what Quizzer said and what `score` was.
async function playQuiz(vm, answers, {waitForScore = true} = {}) {
  const score = () => num(Harness.valueOf(vm, 'score', {spriteName: 'Quizzer'}));
  const stale = Harness.findVariable(vm, 'score', {spriteName: 'Quizzer'});
  if (stale) stale.value = 5; // the green flag must reset it
  const speech = Harness.recordSpeech(vm);
  const scoresAtPrompts = [];
  const onQuestion = (question) => { if (question !== null && question !== undefined) scoresAtPrompts.push(score()); };
  vm.runtime.on('QUESTION', onQuestion);
  const questions = Harness.answerQuestions(vm, answers, speech);
  const bubbles = Harness.recordBubbles(vm, 'Quizzer', score); // every bubble, with the score then
  const said = () => speech.texts('Quizzer').map(t => t.trim());
  const feedback = () => said().filter(t => FEEDBACK.includes(t));
  const scoreLine = () => said().slice(-1).filter(t => /^Score:/.test(t))[0];
  try {
    await Harness.start(vm, 0);
    if (await Harness.waitUntil(() => questions.prompts > 0, {timeoutMs: 3000})) {
      await Harness.waitUntil(() => questions.answered === answers.length && feedback().length >= answers.length,
                              {timeoutMs: 6000});
      if (waitForScore) await Harness.waitUntil(() => scoreLine() !== undefined, {timeoutMs: 2500});
      await Harness.wait(150);
    }
    const line = scoreLine();
    const match = line === undefined ? null : /^Score:\s*(-?\d+)$/.exec(line);
    return {feedback: feedback(), said: said(), scoresAtPrompts, finalScore: score(),
            announced: match ? num(match[1]) : null, bubbles};
  } finally {
    bubbles.stop();
    vm.runtime.removeListener('QUESTION', onQuestion);
    questions.stop();
    speech.stop();
  }
}

function scoreTest(vm, answers, expectedAtPrompts, expected) {
  return async () => {
    const {bubbles, ...result} = await playQuiz(vm, answers);
    const passed = result.scoresAtPrompts.length === 2 &&
      result.scoresAtPrompts.every((s, i) => s === expectedAtPrompts[i]) &&
      result.finalScore === expected && result.announced === expected;
    return {passed, meta: result};
  };
}

module.exports = async (vm) => Harness.runTests(vm, [
  {
    name: 'base: the two questions as written, each feedback shown for 0.5 seconds',
    timeoutMs: 25000,
    run: async () => {
      // Right then wrong, and wrong then right: all four feedback blocks show once.
      const games = [await playQuiz(vm, [12, 4]), await playQuiz(vm, [5, 6])];
      const asked = games.map(game => game.bubbles.changes.map(e => e.text).filter(t => /^what is/i.test(t)).join('|'));
      // Each feedback's bubble: how long it stayed, and the score when it appeared.
      const shown = games.map(game => game.bubbles.shown(FEEDBACK));
      const passed = asked.every(a => a === 'What is 7 + 5?|What is 9 - 3?') &&
        shown.every(fs => fs.length === 2 && fs.every(f => f.ms !== null && f.ms >= 350 && f.ms <= 900));
      return {passed, meta: {asked, shown}};
    },
  },
  {
    name: 'score goes up right after a correct answer, before its feedback',
    timeoutMs: 15000,
    run: async () => {
      const game = await playQuiz(vm, [12, 6]);
      const scores = game.bubbles.shown(FEEDBACK).map(f => f.value);
      return {passed: scores.join(',') === '1,2', meta: {scores}};
    },
  },
  {
    name: 'base: each answer gets "Correct!" or "Wrong!" feedback',
    timeoutMs: 20000,
    run: async () => {
      const first = await playQuiz(vm, [12, 5], {waitForScore: false});
      const second = await playQuiz(vm, [11, 6], {waitForScore: false});
      const passed = first.feedback.join('|') === 'Correct!|Wrong!' && second.feedback.join('|') === 'Wrong!|Correct!';
      return {passed, meta: {first: first.feedback, second: second.feedback}};
    },
  },
  {
    name: 'two right answers: score goes 0, 1, 2 and Quizzer says "Score: 2"',
    timeoutMs: 15000,
    run: scoreTest(vm, [12, 6], [0, 1], 2),
  },
  {
    name: 'only the second answer right (after a previous game): "Score: 1"',
    timeoutMs: 15000,
    run: scoreTest(vm, [4, 6], [0, 0], 1),
  },
  {
    name: 'no right answers: score stays 0 and Quizzer says "Score: 0"',
    timeoutMs: 15000,
    run: scoreTest(vm, ['twelve', 7], [0, 0], 0),
  },
]);
