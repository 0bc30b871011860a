// create/star_shower: on the green flag the hidden Star makes 5 clones, 0.2 s apart; each
// clone starts at y 170 at a random x, falls 10 at a time and deletes itself below y -160.

// Runs the green flag and samples every Star clone once per frame (after each VM step).
async function watchShower(vm) {
  const star = Harness.sprite(vm, 'Star');
  const seen = new Map(); // clone id -> {order, firstMs, samples: [{x, y, visible}]}
  let alive = 0;
  let started = 0;
  const sampler = Harness.sampleFrames(vm, () => {
    const live = Harness.clones(vm, 'Star');
    alive = live.length;
    for (const clone of live) {
      if (!seen.has(clone.id)) seen.set(clone.id, {order: seen.size, firstMs: Date.now() - started, samples: []});
      seen.get(clone.id).samples.push({x: clone.x, y: clone.y, visible: clone.visible});
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
      frames: c.samples.length,
      shownFrames: shown.length,
      firstShown: shown.length ? {x: Math.round(shown[0].x), y: Math.round(shown[0].y)} : null,
      lastY: c.samples.length ? Math.round(c.samples[c.samples.length - 1].y) : null,
      falling: shown.every((s, i) => i === 0 || s.y <= shown[i - 1].y),
      drop: shown.length ? shown[0].y - shown[shown.length - 1].y : 0,
    };
  });
  return {clones, alive: Harness.clones(vm, 'Star').length, originalVisible: star.visible};
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
        const {clones, originalVisible} = await watch();
        const times = clones.map(c => c.firstMs);
        const spread = times.length ? Math.max(...times) - Math.min(...times) : 0;
        // 4 waits of 0.2 s separate the first clone from the fifth.
        return {passed: clones.length === 5 && spread >= 500 && originalVisible === false,
                meta: {clones: clones.length, spread_ms: spread, originalVisible}};
      },
    },
    {
      name: 'each clone shows at the top at a random x and falls down step by step',
      timeoutMs: 20000,
      run: async () => {
        const {clones} = await watch();
        const good = c => c.firstShown && c.firstShown.y >= 140 && Math.abs(c.firstShown.x) <= 201 &&
          c.falling && c.drop >= 250 && c.shownFrames >= 10;
        const xs = new Set(clones.map(c => c.firstShown && c.firstShown.x));
        return {passed: clones.length === 5 && clones.every(good) && xs.size >= 2,
                meta: {clones: clones.map(c => ({start: c.firstShown, drop: Math.round(c.drop), frames: c.shownFrames,
                                                 falling: c.falling}))}};
      },
    },
    {
      name: 'clones delete themselves at the bottom, leaving none',
      timeoutMs: 20000,
      run: async () => {
        const {clones, alive} = await watch();
        return {passed: clones.length === 5 && alive === 0 && clones.every(c => c.lastY !== null && c.lastY <= -150),
                meta: {created: clones.length, remaining: alive, lastY: clones.map(c => c.lastY)}};
      },
    },
  ]);
};
