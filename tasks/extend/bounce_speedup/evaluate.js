// extend/bounce_speedup: the base ball (green flag -> (0, 0), heading right, speed 15, forever
// move speed steps + bounce) must keep working; each bounce must now add 1 to `speed`, and the
// ball must really move that many steps per frame.

// A number from a Scratch value; NaN for empty text, so '' never passes as 0.
const num = v => (typeof v === 'number' ? v : (typeof v === 'string' && v.trim() !== '' ? Number(v) : NaN));

// Green flag, then one sample of Ball per frame (after each VM step) until `bounces` bounces
// and a few frames more. Frames are split into segments between bounces (direction flips).
async function watchBall(vm, bounces) {
  const ball = Harness.sprite(vm, 'Ball');
  const frames = [];
  const sampler = Harness.sampleFrames(vm, () => {
    frames.push({x: ball.x, y: ball.y, dir: ball.direction,
                 speed: num(Harness.valueOf(vm, 'speed', {spriteName: 'Ball'}))});
  });
  // Frames from the green flag's reset on: the first one at y 0 heading right.
  const begin = () => frames.findIndex(f => Math.abs(f.y) < 1 && f.dir > 0 && Math.abs(f.x) < 100);
  const flips = () => {
    const from = begin();
    return from < 0 ? 0 : frames.filter((f, i) => i > from && Math.sign(f.dir) !== Math.sign(frames[i - 1].dir)).length;
  };
  try {
    ball.setXY(100, 50);
    ball.setDirection(-90);
    const speed = Harness.findVariable(vm, 'speed', {spriteName: 'Ball'});
    if (speed) speed.value = 40;
    await Harness.start(vm, 0);
    const moving = () => frames.some(f => Math.abs(f.x) > 0 && Math.abs(f.x - 100) > 0.01);
    if (await Harness.waitUntil(moving, {timeoutMs: 3000})) {
      await Harness.waitUntil(() => flips() >= bounces, {timeoutMs: 12000});
      const enough = frames.length + 6;
      await Harness.waitUntil(() => frames.length >= enough, {timeoutMs: 2000});
    }
  } finally {
    sampler.stop();
  }
  const from = begin();
  const run = from < 0 ? [] : frames.slice(from);
  const segments = [];
  let current = [];
  for (let i = 1; i < run.length; i++) {
    if (Math.sign(run[i].dir) !== Math.sign(run[i - 1].dir)) { // a bounce
      segments.push(current);
      current = [];
      continue;
    }
    current.push({step: Math.abs(run[i].x - run[i - 1].x), speed: run[i].speed});
  }
  segments.push(current);
  return {frames: run, segments, flips: segments.length - 1};
}

// Whether at least 80% of a segment's samples (after its first two) have `key` equal to `value`.
function mostly(segment, key, value) {
  const inner = segment.slice(2);
  const hits = inner.filter(s => Math.abs(s[key] - value) < 0.01).length;
  return inner.length >= 4 && hits >= 0.8 * inner.length;
}

const summary = (segments, key) => segments.map(seg => seg.slice(2).map(s => Math.round(s[key] * 100) / 100));

module.exports = async (vm) => {
  // One green-flag run (three bounces) is watched once and judged by every test.
  let watched = null;
  const watch = () => (watched = watched || watchBall(vm, 3));
  return Harness.runTests(vm, [
    {
      name: 'base: the ball starts at (0, 0) heading right and bounces between the side edges',
      timeoutMs: 20000,
      run: async () => {
        const {frames, flips} = await watch();
        const xs = frames.map(f => f.x);
        const flat = frames.every(f => Math.abs(f.y) < 1);
        const inside = xs.every(x => x >= -240 && x <= 240);
        // Exactly from (0, 0): the first frame shows it there, or one 15-step move to the right of it.
        const first = frames.length ? frames[0] : null;
        const fromOrigin = first !== null && Math.abs(first.y) < 1e-6 &&
          (Math.abs(first.x) < 1e-6 || Math.abs(first.x - 15) < 1e-6);
        return {passed: frames.length > 0 && flips >= 2 && flat && inside && fromOrigin &&
                        Math.max(...xs) > 200 && Math.min(...xs) < -200,
                meta: {frames: frames.length, flips, flat, inside, first,
                       minX: frames.length ? Math.min(...xs) : null, maxX: frames.length ? Math.max(...xs) : null}};
      },
    },
    {
      name: 'speed is 15 at the start and goes up by 1 at each bounce (16, then 17)',
      timeoutMs: 20000,
      run: async () => {
        const {segments, flips} = await watch();
        const ok = flips >= 3 && [0, 1, 2].every(k => mostly(segments[k], 'speed', 15 + k));
        return {passed: ok, meta: {flips, speed: summary(segments.slice(0, 3), 'speed')}};
      },
    },
    {
      name: 'the ball really moves 15, then 16, then 17 steps per frame',
      timeoutMs: 20000,
      run: async () => {
        const {segments, flips} = await watch();
        const ok = flips >= 3 && [0, 1, 2].every(k => mostly(segments[k], 'step', 15 + k));
        return {passed: ok, meta: {flips, steps: summary(segments.slice(0, 3), 'step')}};
      },
    },
  ]);
};
