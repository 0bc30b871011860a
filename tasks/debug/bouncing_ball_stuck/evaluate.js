// debug/bouncing_ball_stuck: the Ball must keep bouncing off the edges instead of sticking.
module.exports = async (vm) => {
  const ball = () => Harness.sprite(vm, 'Ball');
  // A fully visible 30 px ball has its centre at most ~225 px from the centre horizontally
  // and ~165 px vertically; a ball pushed against the edge sits further out.
  const inside = b => Math.abs(b.x) <= 232 && Math.abs(b.y) <= 172;
  // Green flag, then wait for the ball to be put back in the centre (it may still be where the
  // previous test left it, so nothing is judged before that).
  const startFromCentre = async () => {
    await Harness.start(vm, 0);
    return Harness.waitUntil(() => Math.hypot(ball().x, ball().y) < 40, {timeoutMs: 3000, intervalMs: 5});
  };

  return Harness.runTests(vm, [
    {
      name: 'the ball starts in the centre and flies off diagonally',
      timeoutMs: 8000,
      run: async () => {
        // Put it somewhere else first; then its first two frames' positions: the first step goes from
        // (0, 0) along a diagonal (direction 45, 135, -45 or -135), so both lie on that ray.
        ball().setXY(100, -50);
        ball().setDirection(90);
        const seen = [];
        const sampler = Harness.sampleFrames(vm, () => { if (seen.length < 2) seen.push([ball().x, ball().y]); });
        try {
          await Harness.start(vm, 0);
          await Harness.waitUntil(() => seen.length >= 2, {timeoutMs: 3000});
        } finally {
          sampler.stop();
        }
        if (seen.length < 2) return {passed: false, meta: {seen}};
        const [[x1, y1], [x2, y2]] = seen;
        const [vx, vy] = [x2 - x1, y2 - y1];
        const step = Math.hypot(vx, vy);
        const diagonal = step > 0 && Math.abs(Math.abs(vx) - Math.abs(vy)) < 1e-3 * step;
        const fromCentre = Math.abs(x1 * vy - y1 * vx) < 1e-3 * step && x1 * vx + y1 * vy > 0 &&
          Math.hypot(x1, y1) <= step + 1e-3;
        return {passed: diagonal && fromCentre, meta: {seen, diagonal, fromCentre}};
      },
    },
    {
      name: 'the ball moves after the green flag',
      timeoutMs: 8000,
      run: async () => {
        const centred = await startFromCentre();
        const moved = centred && await Harness.waitUntil(() => Math.hypot(ball().x, ball().y) > 100, {timeoutMs: 4000});
        return {passed: centred && moved, meta: {centred, moved, x: ball().x, y: ball().y}};
      },
    },
    {
      name: 'the ball comes back after reaching the right edge',
      timeoutMs: 15000,
      run: async () => {
        const centred = await startFromCentre();
        const reachedRight = centred && await Harness.waitUntil(() => ball().x >= 180, {timeoutMs: 6000});
        const cameBack = reachedRight && await Harness.waitUntil(() => ball().x <= 60, {timeoutMs: 4000});
        return {passed: reachedRight && cameBack, meta: {centred, reachedRight, cameBack, x: ball().x, y: ball().y}};
      },
    },
    {
      name: 'the ball keeps bouncing across the stage and stays inside it',
      timeoutMs: 15000,
      run: async () => {
        const centred = await startFromCentre();
        // Right edge, then left edge, then right again; top and bottom both touched; never out.
        const goals = [b => b.x >= 180, b => b.x <= -180, b => b.x >= 180];
        let reached = 0;
        let top = false;
        let bottom = false;
        let outside = null;
        await Harness.waitUntil(() => {
          const b = ball();
          if (!centred) return true;
          if (!inside(b)) outside = [b.x, b.y];
          if (b.y >= 120) top = true;
          if (b.y <= -120) bottom = true;
          if (reached < goals.length && goals[reached](b)) reached += 1;
          return outside !== null || (reached === goals.length && top && bottom);
        }, {timeoutMs: 10000, intervalMs: 10});
        return {
          passed: centred && outside === null && reached === goals.length && top && bottom,
          meta: {centred, reached, top, bottom, outside},
        };
      },
    },
  ]);
};
