// debug/guess_hints_backwards: the Owl's hints must point the right way.
module.exports = async (vm) => {
  const OWL = 'Owl';
  const secretNow = () => Number(Harness.valueOf(vm, 'secret', {spriteName: OWL}));
  // Guesses inside 1..100 (a game may reject others); the edge numbers fall back to 0 and 101.
  const lowGuess = s => (s > 1 ? Math.max(1, s - 17) : 0);
  const highGuess = s => (s < 100 ? Math.min(100, s + 17) : 101);

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
    try {
      await Harness.start(vm, 0);
      await Harness.waitUntil(() => marks.length === picks.length && replies().every(r => r !== null),
                              {timeoutMs});
      await Harness.wait(settleMs);
      return {secret, guesses, prompts, replies: replies()};
    } finally {
      vm.runtime.removeListener('QUESTION', onQuestion);
      speech.stop();
    }
  }

  return Harness.runTests(vm, [
    {
      name: 'a guess below the secret number gets "Too low!"',
      timeoutMs: 10000,
      run: async () => {
        const game = await play([lowGuess]);
        return {passed: game.replies.length === 1 && game.replies[0] !== null && game.replies[0].trim() === 'Too low!',
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
        return {passed: JSON.stringify(replies) === JSON.stringify(expected) && game.prompts === 3, meta: game};
      },
    },
  ]);
};
