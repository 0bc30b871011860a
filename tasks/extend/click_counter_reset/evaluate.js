// extend/click_counter_reset: the base click counter (green flag -> clicks 0, each click on
// Button adds 1 and says it) must keep working; the new "r" key resets clicks and says "Reset!".

// A number from a Scratch value; NaN for empty text, so '' never passes as 0.
const num = v => (typeof v === 'number' ? v : (typeof v === 'string' && v.trim() !== '' ? Number(v) : NaN));

module.exports = async (vm) => {
  const clicks = () => num(Harness.valueOf(vm, 'clicks', {spriteName: 'Button'}));

  // Clicks Button `times` times, waiting for each click to count before the next.
  async function click(times, speech) {
    for (let i = 0; i < times; i++) {
      const before = clicks();
      Harness.clickSprite(vm, 'Button');
      if (!(await Harness.waitUntil(() => clicks() === before + 1, {timeoutMs: 2000}))) return false;
      await Harness.waitUntil(() => num(speech.texts('Button').slice(-1)[0]) === before + 1, {timeoutMs: 1000});
    }
    return true;
  }

  // Green flag, then wait until the counter is at 0.
  async function restart() {
    const counter = Harness.findVariable(vm, 'clicks', {spriteName: 'Button'});
    if (counter) counter.value = 9;
    await Harness.start(vm, 0);
    return Harness.waitUntil(() => clicks() === 0, {timeoutMs: 2000});
  }

  // Presses "r"; resolves once clicks is 0 and Button has said "Reset!" (or the wait runs out).
  async function reset(speech) {
    const mark = speech.events.length;
    await Harness.pressKey(vm, 'r', 120);
    const said = () => speech.events.slice(mark).some(e => e.sprite === 'Button' && e.text.trim() === 'Reset!');
    return Harness.waitUntil(() => clicks() === 0 && said(), {timeoutMs: 2500});
  }

  return Harness.runTests(vm, [
    {
      name: 'base: green flag sets clicks to 0; each click adds 1 and Button says it',
      timeoutMs: 12000,
      run: async () => {
        const speech = Harness.recordSpeech(vm);
        try {
          const started = await restart();
          const counted = started && await click(3, speech);
          await Harness.wait(200);
          const texts = speech.texts('Button');
          const numbers = texts.filter(t => t.trim() !== 'Click me!').map(num);
          return {passed: counted && clicks() === 3 && texts[0] === 'Click me!' &&
                          numbers.join(',') === '1,2,3',
                  meta: {clicks: clicks(), texts}};
        } finally {
          speech.stop();
        }
      },
    },
    {
      name: 'pressing r sets clicks back to 0 and Button says "Reset!"',
      timeoutMs: 12000,
      run: async () => {
        const speech = Harness.recordSpeech(vm);
        try {
          if (!(await restart()) || !(await click(3, speech))) {
            return {passed: false, meta: {reason: 'the click counter does not work', clicks: clicks()}};
          }
          const done = await reset(speech);
          await Harness.wait(300); // stays reset
          return {passed: done && clicks() === 0, meta: {clicks: clicks(), texts: speech.texts('Button')}};
        } finally {
          speech.stop();
        }
      },
    },
    {
      name: 'after a reset, clicks count up from 1 again (and r works more than once)',
      timeoutMs: 15000,
      run: async () => {
        const speech = Harness.recordSpeech(vm);
        try {
          if (!(await restart()) || !(await click(2, speech))) {
            return {passed: false, meta: {reason: 'the click counter does not work', clicks: clicks()}};
          }
          const first = await reset(speech);
          const counted = first && await click(2, speech);
          const afterClicks = clicks();
          const second = counted && await reset(speech);
          return {passed: first && counted && afterClicks === 2 && second && clicks() === 0,
                  meta: {afterClicks, clicks: clicks(), texts: speech.texts('Button')}};
        } finally {
          speech.stop();
        }
      },
    },
  ]);
};
