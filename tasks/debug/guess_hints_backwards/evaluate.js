// debug/guess_hints_backwards: the Owl's hints must point the right way.
module.exports = async (vm) => {
  const OWL = 'Owl';
  const secretNow = () => Number(Harness.valueOf(vm, 'secret', {spriteName: OWL}));
  // Guesses inside 1..100 (a game may reject others); the edge numbers fall back to 0 and 101.
  const lowGuess = s => (s > 1 ? Math.max(1, s - 17) : 0);
  const highGuess = s => (s < 100 ? Math.min(100, s + 17) : 101);
  const HINTS = ['Too low!', 'Too high!', 'You got it!'];

  // The secret picked with Math.random fixed at `value`, read when the first question is asked.
  async function secretUnder(value) {
    let asked = false;
    const onQuestion = (question) => { if (question !== null && question !== undefined) asked = true; };
    vm.runtime.on('QUESTION', onQuestion);
    try {
      return await Harness.withRandom(value, async () => {
        await Harness.start(vm, 0);
        return (await Harness.waitUntil(() => asked, {timeoutMs: 4000})) ? secretNow() : null;
      });
    } finally {
      vm.runtime.removeListener('QUESTION', onQuestion);
      vm.runtime.stopAll();
    }
  }

  // Green flag, then answer each prompt with pick(secret, index) until `count` answers are given.
  // A reply is the first thing the Owl says after an answer. Resolves once every answer has a
  // reply (or `timeoutMs` passes) and `settleMs` more have passed, so a further prompt is seen.
  async function play(picks, {timeoutMs = 5000, settleMs = 700} = {}) {
    const speech = Harness.recordSpeech(vm);
    const marks = [];
    const guesses = [];
    let prompts = 0;
    let secret = null;
    const onQuestion = (question) => {
      if (question === null || question === undefined) return;
      prompts += 1;
      if (guesses.length >= picks.length) return;
      secret = secretNow();
      const guess = picks[guesses.length](secret);
      guesses.push(guess);
      setTimeout(() => {
        marks.push(speech.events.length);
        vm.runtime.emit('ANSWER', String(guess));
      }, 30);
    };
    const replies = () => marks.map(mark => {
      const reply = speech.events.slice(mark).find(e => e.sprite === OWL);
      return reply ? reply.text : null;
    });
    vm.runtime.on('QUESTION', onQuestion);
    const bubbles = Harness.recordBubbles(vm, OWL, secretNow); // every bubble, with the secret then
    const stale = Harness.findVariable(vm, 'secret', {spriteName: OWL});
    if (stale) stale.value = 0; // the green flag must pick a new one
    try {
      await Harness.start(vm, 0);
      await Harness.waitUntil(() => marks.length === picks.length && replies().every(r => r !== null),
                              {timeoutMs});
      await Harness.wait(settleMs);
      // What the Owl said before the first answer: its hints and "You got it!" must wait for a guess.
      const early = speech.events.slice(0, marks.length ? marks[0] : speech.events.length)
        .filter(e => e.sprite === OWL && HINTS.includes(e.text.trim())).map(e => e.text);
      // How long each "Too high!"/"Too low!" stayed (until the bubble next changed).
      const hints = bubbles.shown(['Too low!', 'Too high!']).map(h => h.ms);
      return {secret, guesses, prompts, replies: replies(), early, hints_ms: hints, opening: bubbles.changes.slice(0, 2)};
    } finally {
      bubbles.stop();
      vm.runtime.removeListener('QUESTION', onQuestion);
      speech.stop();
    }
  }

  return Harness.runTests(vm, [
    {
      name: 'the secret number is picked from 1 to 100, both ends included',
      timeoutMs: 12000,
      run: async () => {
        const lowest = await secretUnder(0);
        const highest = await secretUnder(0.9999999);
        return {passed: lowest === 1 && highest === 100, meta: {lowest, highest}};
      },
    },
    {
      name: 'the game opens as before: the secret picked, "I\'m thinking of a number..." for 0.5 s, then the question',
      timeoutMs: 10000,
      run: async () => {
        const game = await play([lowGuess]);
        const [intro, question] = game.opening;
        const passed = intro !== undefined && question !== undefined && intro.text === "I'm thinking of a number..." &&
          intro.value >= 1 && intro.value <= 100 && question.t - intro.t >= 350 && question.t - intro.t <= 900 &&
          question.text === 'Guess my number between 1 and 100!';
        return {passed, meta: {opening: game.opening.map(b => ({text: b.text, secret: b.value}))}};
      },
    },
    {
      name: 'a guess below the secret number gets "Too low!"',
      timeoutMs: 10000,
      run: async () => {
        const game = await play([lowGuess]);
        return {passed: game.replies.length === 1 && game.replies[0] !== null && game.replies[0].trim() === 'Too low!' &&
                        game.early.length === 0,
                meta: game};
      },
    },
    {
      name: 'a guess above the secret number gets "Too high!"',
      timeoutMs: 10000,
      run: async () => {
        const game = await play([highGuess]);
        return {passed: game.replies.length === 1 && game.replies[0] !== null && game.replies[0].trim() === 'Too high!',
                meta: game};
      },
    },
    {
      name: 'a whole game: low, high, then the right number, and no more questions',
      timeoutMs: 14000,
      run: async () => {
        const game = await play([lowGuess, highGuess, s => s], {timeoutMs: 8000});
        const expected = ['Too low!', 'Too high!', 'You got it!'];
        const replies = game.replies.map(r => (r === null ? null : r.trim()));
        const halfSecond = game.hints_ms.length === 2 && game.hints_ms.every(ms => ms !== null && ms >= 350 && ms <= 900);
        return {passed: JSON.stringify(replies) === JSON.stringify(expected) && game.prompts === 3 && halfSecond,
                meta: game};
      },
    },
  ]);
};
