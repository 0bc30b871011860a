// create/countdown_launch: Commander counts down 5..1 in `count`, says "Liftoff!", broadcasts
// `launch`; Rocket waits at (0, -120) and glides to (0, 150) when it receives `launch`.

// A number from a Scratch value; NaN for empty text, so '' never passes as 0.
const num = v => (typeof v === 'number' ? v : (typeof v === 'string' && v.trim() !== '' ? Number(v) : NaN));

// Speech (with the value of `count` at that moment) and broadcasts, in one ordered log.
function recordLaunch(vm) {
  const log = [];
  const started = Date.now();
  let frames = 0; // VM steps since recording began: "at once" counted in frames, which load cannot stretch
  const sampler = Harness.sampleFrames(vm, () => { frames += 1; });
  const onSay = (target, type, text) => {
    if (text === '' || text === null || text === undefined || !target.sprite) return;
    const count = num(Harness.valueOf(vm, 'count', {spriteName: 'Commander'}));
    const entry = {kind: 'say', sprite: target.sprite.name, text: String(text).trim(), count, countLater: null,
                   t: Date.now() - started, frame: frames};
    log.push(entry);
    // Halfway through the step's 0.3 s wait, `count` still holds the number said (it changes after the wait).
    setTimeout(() => { entry.countLater = num(Harness.valueOf(vm, 'count', {spriteName: 'Commander'})); }, 150);
  };
  const runtime = vm.runtime;
  const original = runtime.startHats;
  runtime.startHats = function (opcode, matchFields) {
    if (opcode === 'event_whenbroadcastreceived' && matchFields && matchFields.BROADCAST_OPTION) {
      log.push({kind: 'broadcast', name: String(matchFields.BROADCAST_OPTION), t: Date.now() - started});
    }
    return original.apply(this, arguments);
  };
  runtime.on('SAY', onSay);
  return {
    log,
    says: () => log.filter(e => e.kind === 'say' && e.sprite === 'Commander'),
    launches: () => log.filter(e => e.kind === 'broadcast' && e.name === 'launch'),
    stop: () => { runtime.removeListener('SAY', onSay); runtime.startHats = original; sampler.stop(); },
  };
}

// Commander's speech with repeats of the same text in a row collapsed.
function distinctSays(rec) {
  const out = [];
  for (const e of rec.says()) {
    if (!out.length || out[out.length - 1].text !== e.text) out.push(e);
  }
  return out;
}

const EXPECTED = ['5', '4', '3', '2', '1', 'Liftoff!'];
const sameText = (said, expected) =>
  (/^\d+$/.test(expected) ? num(said) === Number(expected) : said === expected);

module.exports = async (vm) => Harness.runTests(vm, [
  {
    name: 'Commander says 5, 4, 3, 2, 1 (matching count) and then Liftoff!',
    timeoutMs: 15000,
    run: async () => {
      const rec = recordLaunch(vm);
      try {
        await Harness.start(vm, 0);
        if (await Harness.waitUntil(() => rec.says().length > 0, {timeoutMs: 3000})) {
          await Harness.waitUntil(() => rec.says().some(e => e.text === 'Liftoff!'), {timeoutMs: 9000});
          await Harness.wait(300);
        }
        const says = distinctSays(rec);
        const texts = says.map(e => e.text);
        const order = texts.length === EXPECTED.length && texts.every((t, i) => sameText(t, EXPECTED[i]));
        // Every time a number is said, `count` holds that number, and still does halfway through its wait.
        const numbers = rec.says().filter(e => e.text !== 'Liftoff!');
        const counted = numbers.length > 0 && numbers.every(e => e.count === num(e.text) && e.countLater === e.count);
        // "5" at once, then 0.3 s between one step's words and the next, "1" and "Liftoff!" included.
        // (Windows leave a loaded machine's real clock room; a wrong wait, 0.6 s or more, is still outside.)
        const gaps = says.slice(1).map((e, i) => e.t - says[i].t);
        const paced = order && says[0].frame <= 2 && gaps.every(gap => gap >= 200 && gap <= 550);
        return {passed: order && counted && paced,
                meta: {texts, counts: numbers.map(e => [e.count, e.countLater]), first_frame: says.length ? says[0].frame : null,
                       gaps_ms: gaps}};
      } finally {
        rec.stop();
      }
    },
  },
  {
    name: 'launch is broadcast once, after Commander says Liftoff!',
    timeoutMs: 15000,
    run: async () => {
      const rec = recordLaunch(vm);
      try {
        await Harness.start(vm, 0);
        if (await Harness.waitUntil(() => rec.log.length > 0, {timeoutMs: 3000})) {
          await Harness.waitUntil(() => rec.launches().length > 0, {timeoutMs: 9000});
          await Harness.wait(500);
        }
        const launches = rec.launches();
        const launchAt = launches.length ? rec.log.indexOf(launches[0]) : -1;
        const liftoffAt = rec.log.findIndex(e => e.kind === 'say' && e.sprite === 'Commander' && e.text === 'Liftoff!');
        const oneAt = rec.log.findIndex(e => e.kind === 'say' && e.sprite === 'Commander' && num(e.text) === 1);
        return {passed: launches.length === 1 && oneAt >= 0 && oneAt < liftoffAt && liftoffAt < launchAt,
                meta: {log: rec.log.map(e => (e.kind === 'say' ? `${e.sprite}: ${e.text}` : `broadcast ${e.name}`))}};
      } finally {
        rec.stop();
      }
    },
  },
  {
    name: 'Rocket waits at (0, -120) until launch, then glides up to (0, 150)',
    timeoutMs: 15000,
    run: async () => {
      const rocket = Harness.sprite(vm, 'Rocket');
      rocket.setXY(60, 100);
      const near = (x, y) => Math.abs(rocket.x - x) < 0.5 && Math.abs(rocket.y - y) < 0.5;
      const rec = recordLaunch(vm);
      try {
        await Harness.start(vm, 0);
        // On the pad at once, on the green flag (long before the countdown ends).
        if (!(await Harness.waitUntil(() => near(0, -120), {timeoutMs: 500})) || rec.launches().length) {
          return {passed: false, meta: {reason: 'Rocket did not go to (0, -120) on the flag', x: rocket.x, y: rocket.y}};
        }
        // Until launch, it stays on the pad.
        let leftEarly = false;
        await Harness.waitUntil(() => {
          if (rec.launches().length) return true;
          if (!near(0, -120)) leftEarly = true;
          return false;
        }, {timeoutMs: 8000, intervalMs: 10});
        if (!rec.launches().length || leftEarly) {
          return {passed: false, meta: {reason: leftEarly ? 'Rocket moved before launch' : 'no launch broadcast'}};
        }
        const launchedAt = Date.now();
        const between = [];
        const arrived = await Harness.waitUntil(() => {
          if (rocket.y > -110 && rocket.y < 140) between.push(Math.round(rocket.y));
          return near(0, 150);
        }, {timeoutMs: 5000, intervalMs: 10});
        const took = Date.now() - launchedAt;
        // A glide, not a jump: seen on the way up, and it takes about 1 second.
        return {passed: arrived && between.length >= 3 && took >= 700 && took <= 1600,
                meta: {arrived, took_ms: took, seen_between: between.length, x: rocket.x, y: rocket.y}};
      } finally {
        rec.stop();
      }
    },
  },
]);
