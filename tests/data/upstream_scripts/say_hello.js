// Test script for the upstream say_hello task (written here): Sprite1 says "hello" on the flag.
module.exports = async (vm, config, cleanup) => {
  const replies = await EvaluationUtils.collectReplies(vm, 'Sprite1', [], 3000);
  cleanup();
  const passed = replies.some(text => text.trim().toLowerCase() === 'hello');
  return {
    success: passed,
    passed_tests: passed ? 1 : 0,
    total_tests: 1,
    partial_success_rate: passed ? 1 : 0,
    details: [{name: 'says hello', passed, meta: {replies}}],
  };
};
