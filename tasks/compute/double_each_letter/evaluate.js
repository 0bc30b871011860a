// compute/double_each_letter: the Parrot asks for a word and says it with every character doubled.
module.exports = async (vm) => {
  const cases = [['cat', 'ccaatt'], ['Scratch', 'SSccrraattcchh'], ['No 1!', 'NNoo  11!!']];
  return Harness.runTests(vm, cases.map(([word, expected]) => ({
    name: `"${word}" becomes "${expected}"`,
    timeoutMs: 8000,
    run: async () => {
      const {prompts, replies, asked} = await Harness.askAndListen(vm, 'Parrot', [word]);
      // One prompt, with a text (an empty prompt asks for nothing); exactly one reply, equal to the expected
      // text (case and inner spaces count).
      return {passed: prompts === 1 && asked.every(q => q.trim() !== '') && replies.length === 1 &&
                      replies[0].trim() === expected,
              meta: {prompts, asked, replies}};
    },
  })));
};
