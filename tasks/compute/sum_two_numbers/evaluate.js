// compute/sum_two_numbers: the sprite asks for two numbers and says their sum.
module.exports = async (vm) => {
  const cases = [[[3, 4], 7], [[10, -2], 8], [[2.5, 0.5], 3]];
  return Harness.runTests(vm, cases.map(([inputs, expected]) => ({
    name: `${inputs.join(' + ')} = ${expected}`,
    timeoutMs: 8000,
    run: async () => {
      const {prompts, replies, asked} = await Harness.askAndListen(vm, 'Calculator', inputs);
      // Two questions, each with a text (an empty prompt asks for nothing); exactly one reply, and it is the
      // number itself (not "6.9" for 6, not "the sum is 7").
      return {passed: asked.length === 2 && asked.every(q => q.trim() !== '') &&
                      replies.length === 1 && replies[0].trim() !== '' && Number(replies[0]) === expected,
              meta: {prompts, asked, replies}};
    },
  })));
};
