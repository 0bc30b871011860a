// debug/traffic_light_skips_yellow: the Light must cycle green -> yellow -> red -> green.
module.exports = async (vm) => {
  const colour = () => {
    const light = Harness.sprite(vm, 'Light');
    return light.getCostumes()[light.currentCostume].name;
  };
  const NEXT = {green: 'yellow', yellow: 'red', red: 'green'};

  // Green flag, then the light's colours as they change (repeats collapsed), sampled until
  // `done(colours)` or `timeoutMs`. The light is set to "red" first, so "green" must be switched on.
  async function watch(done, timeoutMs) {
    const light = Harness.sprite(vm, 'Light');
    const red = light.getCostumes().findIndex(c => c.name === 'red');
    if (red >= 0) light.setCostume(red);
    const colours = [];
    await Harness.start(vm, 0);
    await Harness.waitUntil(() => {
      const now = colour();
      if (colours[colours.length - 1] !== now) colours.push(now);
      return done(colours);
    }, {timeoutMs, intervalMs: 10});
    return colours;
  }
  // Changes after the first "green" (the light starts red, before the first message).
  const fromGreen = colours => colours.slice(Math.max(0, colours.indexOf('green')));
  const legal = colours => fromGreen(colours).every((c, i, all) => i === 0 || NEXT[all[i - 1]] === c);

  return Harness.runTests(vm, [
    {
      name: 'the light turns green when the flag is clicked',
      timeoutMs: 6000,
      run: async () => {
        const colours = await watch(cs => cs.includes('green'), 2000);
        return {passed: colours.includes('green'), meta: {colours}};
      },
    },
    {
      name: 'yellow shows between green and red',
      timeoutMs: 8000,
      run: async () => {
        const seen = cs => fromGreen(cs).join(',').includes('green,yellow,red');
        const colours = await watch(seen, 4000);
        return {passed: seen(colours), meta: {colours}};
      },
    },
    {
      name: 'two full cycles change only green -> yellow -> red -> green',
      timeoutMs: 12000,
      run: async () => {
        // Stops early on a wrong change; needs g,y,r,g,y,r,g.
        const colours = await watch(cs => !legal(cs) || fromGreen(cs).length >= 7, 7000);
        const cycle = fromGreen(colours);
        return {passed: cycle[0] === 'green' && legal(colours) && cycle.length >= 7, meta: {colours}};
      },
    },
    {
      name: 'each colour lasts as long as it should: green 0.6 s, yellow 0.3 s, red 0.6 s',
      timeoutMs: 15000,
      run: async () => {
        // Every change of colour, timed: the phases of two full cycles and the next green.
        const changes = [];
        const sampler = Harness.sampleFrames(vm, () => {
          const now = colour();
          if (!changes.length || changes[changes.length - 1].colour !== now) changes.push({colour: now, t: Date.now()});
        });
        try {
          await watch(cs => fromGreen(cs).length >= 8 || !legal(cs), 9000);
        } finally {
          sampler.stop();
        }
        const cycle = changes.slice(Math.max(0, changes.findIndex(c => c.colour === 'green')));
        const phases = cycle.slice(1).map((c, i) => ({colour: cycle[i].colour, ms: c.t - cycle[i].t}));
        // Windows around 0.6, 0.3 and 0.6 s with room for a loaded real clock; 0 s, or 1 s and more, are outside.
        const WINDOW = {green: [450, 900], yellow: [200, 500], red: [450, 900]};
        // The second cycle: the first one's timers start while the page warms up.
        const timed = phases.length >= 6 &&
          phases.slice(3, 6).every(p => p.ms >= WINDOW[p.colour][0] && p.ms <= WINDOW[p.colour][1]);
        return {passed: timed && phases[3].colour === 'green', meta: {phases}};
      },
    },
    {
      name: 'the messages go, slow, stop are broadcast in that order, then go again',
      timeoutMs: 8000,
      run: async () => {
        const broadcasts = Harness.recordBroadcasts(vm);
        try {
          await Harness.start(vm, 0);
          await Harness.waitUntil(() => broadcasts.names().length >= 4, {timeoutMs: 4000});
          const names = broadcasts.names().slice(0, 4).map(n => n.toLowerCase());
          return {passed: names.join(',') === 'go,slow,stop,go', meta: {names: broadcasts.names()}};
        } finally {
          broadcasts.stop();
        }
      },
    },
  ]);
};
