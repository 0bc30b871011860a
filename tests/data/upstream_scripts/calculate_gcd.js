// Test script for the upstream calculate_gcd task (written here); reports details only, as some
// upstream scripts do, so the evaluator has to derive the counts.
module.exports = async (vm) => {
  const cases = [[[12, 18], 6], [[7, 13], 1], [[20, 10], 10]];
  const details = [];
  for (const [inputs, expected] of cases) {
    const replies = await EvaluationUtils.collectReplies(vm, 'Sprite1', inputs, 4000);
    details.push({name: `gcd(${inputs.join(', ')}) = ${expected}`, passed: Number(replies[0]) === expected});
  }
  return {details};
};
