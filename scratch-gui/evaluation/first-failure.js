/*
 * Stopping an evaluation's tests at the first that fails (`evaluate`'s `stopAtFirstFailure`, which the grader
 * audit asks for its mutants): once a test failed, the verdict is "failed" whatever the others would say, so
 * they are not run. The scripts stay as they are; the suite's helper runs their tests, and for the one run this
 * wraps its test runners:
 * - `runCaseWithTimeout(options)` (upstream's EvaluationUtils; every upstream test goes through it, one call
 *   per test, question-and-answer cases included, and the script counts what it returns): once a call returned
 *   a result that did not pass, each later call returns at once a failed result marked as not run, and the
 *   case's beforeCase, run and afterCase are not called;
 * - `runTests(vm, tests)` (our suite's Harness): each test's `run` is wrapped; once a test ended without its
 *   `run` resolving `{passed: true}` before the next test began (it failed, threw or timed out), each later
 *   test's `run` resolves at once `{passed: false}`.
 * The script then ends as it would with those tests failing: its own cleanup runs (its patches undone, the VM
 * stopped) and its report counts them as not passed. `stop` puts the helper back and reports the test that
 * failed first and how many were not run: `{earlyStop: {test, notRun}}`, or nothing when none was skipped.
 */
scratchworldModule({name: 'evaluation/first-failure', create(ctx) {
  'use strict';

  const NOT_RUN = 'not run: an earlier test failed (the evaluation stops at its first failing test)';

  function watch(args) {
    let failed = null; // the name of the first test that failed
    let notRun = 0;
    const undo = [];

    function wrap(helper, name, make) {
      const original = helper[name];
      if (typeof original !== 'function') return;
      helper[name] = make(original);
      undo.push(() => { helper[name] = original; });
    }

    function caseRunner(original) {
      return async function runCaseWithTimeout(options) {
        const name = String((options && options.caseName) || 'case');
        if (failed !== null) {
          notRun += 1;
          return {name: name, passed: false, timeout: false, duration_ms: 0, error: NOT_RUN, meta: {not_run: true}};
        }
        const result = await original.apply(this, arguments);
        if (!(result && result.passed) && failed === null) failed = String((result && result.name) || name);
        return result;
      };
    }

    function testsRunner(original) {
      return function runTests(vm, tests) {
        if (!Array.isArray(tests)) return original.apply(this, arguments);
        const passed = tests.map(() => false);
        const wrapped = tests.map((test, index) => {
          if (!test || typeof test.run !== 'function') return test;
          return Object.assign({}, test, {
            run: async (...runArgs) => {
              const earlier = passed.slice(0, index).indexOf(false);
              if (failed === null && earlier !== -1) failed = String(tests[earlier].name);
              if (failed !== null) {
                notRun += 1;
                return {passed: false, meta: {not_run: true}};
              }
              const outcome = await test.run(...runArgs);
              passed[index] = !!(outcome && outcome.passed);
              return outcome;
            },
          });
        });
        return original.call(this, vm, wrapped);
      };
    }

    return {
      start() {
        const helper = window[args.helperGlobal || 'EvaluationUtils'];
        if (!helper || typeof helper !== 'object') return; // no helper: its script runs its tests itself
        wrap(helper, 'runCaseWithTimeout', caseRunner);
        wrap(helper, 'runTests', testsRunner);
      },
      stop() {
        for (const put of undo.reverse()) put();
        return failed !== null && notRun > 0 ? {earlyStop: {test: failed, notRun: notRun}} : null;
      },
    };
  }

  // Called by `evaluate` with its arguments, before anything starts: null, or the wrapping's start and stop.
  ctx.onEvaluation((vm, args) => {
    const stop = args.stopAtFirstFailure;
    if (stop == null || stop === false) return null;
    if (stop !== true) throw new ctx.BridgeFailure('bad_request', 'stopAtFirstFailure must be true or false');
    return watch(args);
  });
  return {};
}});
