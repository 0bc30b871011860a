// Timing-sensitive behaviours of tests.support.projects.timing_project, measured on the page's clock: the
// verdicts (and the times, within a frame or two) must be the same under the real and the virtual
// clock. Each test starts its script with a broadcast and watches what the VM does.
'use strict';

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

module.exports = async (vm) => {
  const runtime = vm.runtime;
  let said = [];
  runtime.on('SAY', (target, type, text) => {
    if (text) said.push({sprite: target.sprite.name, text: String(text), t: Date.now()});
  });
  const fire = (name) => runtime.startHats('event_whenbroadcastreceived', {BROADCAST_OPTION: name});
  const sprite = (name) => runtime.targets.find((t) => t.isOriginal && t.getName() === name);
  const stageVar = (name) => Object.values(runtime.getTargetForStage().variables).find((v) => v.name === name);
  const saidBy = (name, text) => said.find((e) => e.sprite === name && e.text === text);
  async function until(predicate, timeoutMs, onPoll = () => {}) {
    const deadline = Date.now() + timeoutMs;
    for (;;) {
      onPoll();
      if (predicate()) return true;
      if (Date.now() > deadline) return false;
      await sleep(10);
    }
  }
  // Starts `message` and waits until `name` says `text`: ms from the broadcast, or null.
  async function timeUntilSaid(message, name, text, timeoutMs, onPoll) {
    const started = Date.now();
    fire(message);
    const ok = await until(() => saidBy(name, text), timeoutMs, onPoll);
    return ok ? saidBy(name, text).t - started : null;
  }

  const tests = [
    ['timers fire in due order, ties in creation order, promise callbacks in between', async () => {
      const order = [];
      setTimeout(() => {
        order.push('b');
        Promise.resolve().then(() => order.push('b-micro'));
      }, 20);
      setTimeout(() => order.push('c'), 20);
      setTimeout(() => order.push('a'), 10);
      await sleep(50);
      return {passed: order.join() === 'a,b,b-micro,c', meta: {order}};
    }],
    ['wait 0.5 seconds', async () => {
      const took = await timeUntilSaid('wait', 'Walker', 'waited', 3000);
      return {passed: took !== null && took >= 450 && took <= 900, meta: {took}};
    }],
    ['glide for 1 second, seen on the way', async () => {
      const walker = sprite('Walker');
      let between = 0;
      const took = await timeUntilSaid('glide', 'Walker', 'glided', 4000, () => {
        if (walker.x > -90 && walker.x < 90) between += 1;
      });
      return {passed: took !== null && took >= 950 && took <= 1500 && between >= 20 && walker.x === 100,
              meta: {took, between, x: walker.x}};
    }],
    ['ask and wait', async () => {
      const answer = (question) => {
        if (question !== null && question !== undefined) setTimeout(() => runtime.emit('ANSWER', 'Ada'), 30);
      };
      runtime.on('QUESTION', answer);
      try {
        const took = await timeUntilSaid('ask', 'Walker', 'hi Ada', 3000);
        return {passed: took !== null && took >= 30 && took <= 300, meta: {took}};
      } finally {
        runtime.removeListener('QUESTION', answer);
      }
    }],
    ['broadcast and wait', async () => {
      const done = stageVar('inner_done');
      done.value = 0;
      let doneWhenSaid = null;
      const took = await timeUntilSaid('chain', 'Walker', 'after inner', 3000, () => {
        if (doneWhenSaid === null && saidBy('Walker', 'after inner')) doneWhenSaid = done.value;
      });
      return {passed: took !== null && took >= 280 && took <= 700 && doneWhenSaid === 1, meta: {took, doneWhenSaid}};
    }],
    ['clones appear, count and delete themselves', async () => {
      const count = stageVar('clones');
      count.value = 0;
      const live = () => runtime.targets.filter((t) => !t.isOriginal && t.sprite.name === 'Walker').length;
      const started = Date.now();
      let most = 0;
      fire('clone');
      const gone = await until(() => Date.now() - started > 300 && live() === 0, 3000, () => { most = Math.max(most, live()); });
      const took = Date.now() - started;
      return {passed: gone && most === 3 && count.value === 3 && took >= 650 && took <= 1200,
              meta: {most, counted: count.value, took}};
    }],
    ['touching a wall, with a loop that never redraws running beside', async () => {
      stageVar('seen').value = 0;
      const mover = sprite('Mover');
      const took = await timeUntilSaid('touch', 'Mover', 'touched', 5000);
      await sleep(200); // the never-redrawing loop keeps running meanwhile
      return {passed: took !== null && took >= 1200 && took <= 2500 && mover.x >= 75 && mover.x <= 90 &&
                      Number(stageVar('seen').value) === 1,
              meta: {took, x: mover.x, seen: stageVar('seen').value}};
    }],
    ['play sound until done lasts the sound (0.6 s)', async () => {
      const took = await timeUntilSaid('sound', 'Speaker', 'sound done', 4000);
      return {passed: took !== null && took >= 550 && took <= 1100, meta: {took}};
    }],
  ];

  const details = [];
  for (const [name, run] of tests) {
    runtime.stopAll();
    said = [];
    details.push({name, ...(await run())});
  }
  runtime.stopAll();
  return {details};
};
