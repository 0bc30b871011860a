// Test helper with the upstream helper's file name and global (EvaluationUtils), written here.
const sleep = ms => new Promise(resolve => setTimeout(resolve, ms));

function spriteByName(vm, name) {
  return vm.runtime.targets.find(t => t.isOriginal && !t.isStage && t.getName() === name) || null;
}

// Green flag, answer each prompt in turn, return what the sprite said after the last answer.
async function collectReplies(vm, spriteName, inputs, timeoutMs) {
  const replies = [];
  let remaining = inputs.map(String);
  let answeredAll = inputs.length === 0;
  const onQuestion = (question) => {
    if (question === null || !remaining.length) return;
    const answer = remaining.shift();
    setTimeout(() => { answeredAll = remaining.length === 0; vm.runtime.emit('ANSWER', answer); }, 30);
  };
  const onSay = (target, type, text) => {
    if (answeredAll && text && target.getName() === spriteName) replies.push(String(text));
  };
  vm.runtime.on('QUESTION', onQuestion);
  vm.runtime.on('SAY', onSay);
  try {
    vm.runtime.stopAll();
    vm.greenFlag();
    const deadline = Date.now() + timeoutMs;
    while (!replies.length && Date.now() < deadline) await sleep(20);
    return replies;
  } finally {
    vm.runtime.removeListener('QUESTION', onQuestion);
    vm.runtime.removeListener('SAY', onSay);
    vm.runtime.stopAll();
  }
}

module.exports = {sleep, spriteByName, collectReplies};
