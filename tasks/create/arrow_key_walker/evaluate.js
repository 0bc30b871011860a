// create/arrow_key_walker: the green flag puts Walker at (0, 0) and `moves` at 0; each arrow-key
// press moves it 10 in that direction, exactly once per press, and adds 1 to `moves`.

// A number from a Scratch value; NaN for empty text, so '' never passes as 0.
const num = v => (typeof v === 'number' ? v : (typeof v === 'string' && v.trim() !== '' ? Number(v) : NaN));

module.exports = async (vm) => {
  const walker = () => Harness.sprite(vm, 'Walker');
  const at = (x, y) => Math.abs(walker().x - x) < 0.01 && Math.abs(walker().y - y) < 0.01;
  const moves = () => num(Harness.valueOf(vm, 'moves', {spriteName: 'Walker'}));
  const where = () => ({x: walker().x, y: walker().y, moves: Harness.valueOf(vm, 'moves', {spriteName: 'Walker'})});

  // Green flag, then wait for Walker to be back at the origin with no moves.
  async function restart() {
    walker().setXY(120, -60);
    const counter = Harness.findVariable(vm, 'moves', {spriteName: 'Walker'});
    if (counter) counter.value = 7;
    await Harness.start(vm, 0);
    return Harness.waitUntil(() => at(0, 0) && moves() === 0, {timeoutMs: 2500});
  }

  // Presses keys one by one; after each, Walker must reach the expected spot.
  async function walk(steps) {
    const path = [];
    for (const [key, x, y, holdMs = 120] of steps) {
      await Harness.pressKey(vm, key, holdMs);
      const reached = await Harness.waitUntil(() => at(x, y), {timeoutMs: 2000});
      path.push({key, ...where()});
      if (!reached) return {ok: false, path};
    }
    await Harness.wait(400); // no late or repeated moves
    path.push({key: '(settled)', ...where()});
    const [, x, y] = steps[steps.length - 1];
    return {ok: at(x, y), path};
  }

  return Harness.runTests(vm, [
    {
      name: 'green flag puts Walker at (0, 0) with moves = 0, and it stays still',
      timeoutMs: 8000,
      run: async () => {
        const reset = await restart();
        let drifted = false;
        await Harness.waitUntil(() => { if (!at(0, 0)) drifted = true; return false; }, {timeoutMs: 600});
        return {passed: reset && !drifted, meta: {reset, drifted, ...where()}};
      },
    },
    {
      name: 'right and left arrows change x by 10 and -10, counting moves',
      timeoutMs: 12000,
      run: async () => {
        if (!(await restart())) return {passed: false, meta: {reason: 'no reset on green flag', ...where()}};
        const {ok, path} = await walk([['right arrow', 10, 0], ['right arrow', 20, 0], ['left arrow', 10, 0]]);
        return {passed: ok && moves() === 3, meta: {path}};
      },
    },
    {
      name: 'up and down arrows change y by 10 and -10, once per press even when held',
      timeoutMs: 12000,
      run: async () => {
        if (!(await restart())) return {passed: false, meta: {reason: 'no reset on green flag', ...where()}};
        const {ok, path} = await walk([
          ['up arrow', 0, 10], ['up arrow', 0, 20], ['down arrow', 0, 10], ['up arrow', 0, 20, 500],
        ]);
        return {passed: ok && moves() === 4, meta: {path}};
      },
    },
  ]);
};
