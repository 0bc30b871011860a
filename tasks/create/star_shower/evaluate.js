// create/star_shower: on the green flag the hidden Star makes 5 clones, 0.2 s apart; each
// clone starts at y 170 at a random x, falls 10 at a time and deletes itself below y -160.

// Runs the green flag and samples every Star clone once per frame (after each VM step).
async function watchShower(vm) {
  const star = Harness.sprite(vm, 'Star');
  const seen = new Map(); // clone (not its id: ids come from Math.random, which a test may fix) -> {order, firstMs, samples: [{x, y, visible}]}
  let alive = 0;
  let started = 0;
  let originalShownFrames = 0;
  let frame = 0;
  const sampler = Harness.sampleFrames(vm, () => {
    frame += 1;
    if (star.visible) originalShownFrames += 1;
    const live = Harness.clones(vm, 'Star');
    alive = live.length;
    for (const clone of live) {
      if (!seen.has(clone)) seen.set(clone, {order: seen.size, firstMs: Date.now() - started, firstFrame: frame, samples: []});
      seen.get(clone).samples.push({x: clone.x, y: clone.y, visible: clone.visible});
    }
  });
  try {
    star.setVisible(true);
    started = Date.now();
    await Harness.start(vm, 0);
    if (await Harness.waitUntil(() => seen.size > 0, {timeoutMs: 3000})) {
      await Harness.waitUntil(() => seen.size >= 5 && alive === 0, {timeoutMs: 10000});
      await Harness.wait(400); // a sixth clone, or one that never goes away
    }
  } finally {
    sampler.stop();
  }
  const clones = [...seen.values()].map(c => {
    const shown = c.samples.filter(s => s.visible);
    return {
      firstMs: c.firstMs,
      firstFrame: c.firstFrame,
      frames: c.samples.length,
      shownFrames: shown.length,
      firstShown: shown.length ? {x: Math.round(shown[0].x), y: Math.round(shown[0].y)} : null,
      // Shown only on its way down from y 170 in steps of 10 (170, 160, ...; which one shows first depends on
      // whether it moved in the frame it appeared).
      onGrid: shown.every(s => s.y <= 170.001 && Math.abs((170 - s.y) / 10 - Math.round((170 - s.y) / 10)) < 1e-6),
      lastY: c.samples.length ? Math.round(c.samples[c.samples.length - 1].y) : null,
      falling: shown.every((s, i) => i === 0 || s.y <= shown[i - 1].y),
      drop: shown.length ? shown[0].y - shown[shown.length - 1].y : 0,
    };
  });
  return {clones, alive: Harness.clones(vm, 'Star').length, originalVisible: star.visible, originalShownFrames};
}

// The x of every clone of one shower with `Math.random` fixed at `value` (both ends of -200..200).
async function showerXs(vm, value) {
  return Harness.withRandom(value, async () => {
    const {clones} = await watchShower(vm);
    return clones.map(c => (c.firstShown ? c.firstShown.x : null));
  });
}

module.exports = async (vm) => {
  // One green-flag shower is watched once and judged by every test.
  let watched = null;
  const watch = () => (watched = watched || watchShower(vm));
  return Harness.runTests(vm, [
    {
      name: 'the hidden Star creates exactly 5 clones, spread over time',
      timeoutMs: 20000,
      run: async () => {
        const {clones, originalVisible, originalShownFrames} = await watch();
        const times = clones.map(c => c.firstMs).sort((a, b) => a - b);
        const gaps = times.slice(1).map((t, i) => t - times[i]);
        const first = Math.min(...clones.map(c => c.firstFrame));
        // The first clone at once (in the first frames), then one every 0.2 s (room for a loaded real clock; a
        // 0.4 s wait is still outside); the original hidden from the first frame on.
        const paced = clones.length > 0 && first <= 2 && gaps.every(gap => gap >= 150 && gap <= 400);
        return {passed: clones.length === 5 && paced && originalVisible === false && originalShownFrames === 0,
                meta: {clones: clones.length, first_frame: clones.length ? first : null, gaps_ms: gaps, originalVisible,
                       originalShownFrames}};
      },
    },
    {
      name: 'each clone shows at the top at a random x and falls down step by step',
      timeoutMs: 20000,
      run: async () => {
        const {clones} = await watch();
        const good = c => c.firstShown && c.firstShown.y >= 150 && Math.abs(c.firstShown.x) <= 201 &&
          c.onGrid && c.falling && c.drop >= 250 && c.shownFrames >= 10;
        const xs = new Set(clones.map(c => c.firstShown && c.firstShown.x));
        return {passed: clones.length === 5 && clones.every(good) && xs.size >= 2,
                meta: {clones: clones.map(c => ({start: c.firstShown, drop: Math.round(c.drop), frames: c.shownFrames,
                                                 falling: c.falling, onGrid: c.onGrid}))}};
      },
    },
    {
      name: 'the random x spans -200 to 200 (both ends reached)',
      timeoutMs: 30000,
      run: async () => {
        const low = await showerXs(vm, 0);
        const high = await showerXs(vm, 0.9999999);
        const all = (xs, x) => xs.length === 5 && xs.every(v => v !== null && Math.abs(v - x) < 0.5);
        return {passed: all(low, -200) && all(high, 200), meta: {low, high}};
      },
    },
    {
      name: 'clones delete themselves once below y -160, leaving none',
      timeoutMs: 20000,
      run: async () => {
        const {clones, alive} = await watch();
        return {passed: clones.length === 5 && alive === 0 && clones.every(c => c.lastY !== null && c.lastY < -160),
                meta: {created: clones.length, remaining: alive, lastY: clones.map(c => c.lastY)}};
      },
    },
  ]);
};
