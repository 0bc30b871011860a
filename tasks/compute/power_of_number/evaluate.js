// compute/power_of_number: the Robot asks for a base and an exponent and says base^exponent.
module.exports = async (vm) => {
  const cases = [[[2, 10], 1024], [[7, 0], 1], [[-3, 3], -27]];
  return Harness.runTests(vm, cases.map(([inputs, expected]) => ({
    name: `${inputs[0]} to the power ${inputs[1]} = ${expected}`,
    timeoutMs: 8000,
    run: async () => {
      const {prompts, replies, asked} = await Harness.askAndListen(vm, 'Robot', inputs);
      // Two prompts, each with a text (an empty prompt asks for nothing); exactly one reply, and it is the
      // number itself.
      return {passed: prompts === 2 && asked.every(q => q.trim() !== '') &&
                      replies.length === 1 && replies[0].trim() !== '' &&
                      Number(replies[0]) === expected,
              meta: {prompts, asked, replies}};
    },
  })));
};
