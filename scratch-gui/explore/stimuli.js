/*
 * What an exploration does to a program (explore/run.js), each as a person would through the GUI: click
 * the green flag, press a key (held, then let go), click a sprite or the stage, switch the backdrop,
 * send a broadcast; and answer every "ask and wait" prompt from a list of answers, in turn. Only the
 * VM's own entry points are used (the same the GUI and the suites' helpers call).
 */
scratchworldModule({name: 'explore/stimuli', create() {
  'use strict';

  const KINDS = ['green_flag', 'key', 'click', 'stage_click', 'backdrop', 'broadcast'];

  // Scratch key names as the keyboard device reads browser keys (the rest are their own character).
  const BROWSER_KEYS = {
    'space': ' ', 'left arrow': 'ArrowLeft', 'right arrow': 'ArrowRight', 'up arrow': 'ArrowUp',
    'down arrow': 'ArrowDown', 'enter': 'Enter',
  };
  const browserKey = (name) => BROWSER_KEYS[name] || name;

  const sprite = (vm, name) => vm.runtime.targets.find((t) => t.isOriginal && !t.isStage && t.getName() === name);

  /**
   * Does `stimulus` ({kind, name, holdMs}) to the program; a held key is let go after `holdMs` (by a timer,
   * kept in `held` until then). Returns whether it found what it acts on (a sprite, a backdrop).
   */
  function apply(vm, stimulus, held) {
    const runtime = vm.runtime;
    switch (stimulus.kind) {
      case 'green_flag':
        vm.greenFlag();
        return true;
      case 'key': {
        const key = browserKey(stimulus.name);
        vm.postIOData('keyboard', {key: key, isDown: true});
        const release = () => {
          held.delete(key);
          vm.postIOData('keyboard', {key: key, isDown: false});
        };
        held.set(key, setTimeout(release, stimulus.holdMs));
        return true;
      }
      case 'click': {
        const target = sprite(vm, stimulus.name);
        if (target) runtime.startHats('event_whenthisspriteclicked', null, target);
        return !!target;
      }
      case 'stage_click':
        runtime.startHats('event_whenstageclicked', null, runtime.getTargetForStage());
        return true;
      case 'backdrop': {
        const stage = runtime.getTargetForStage();
        const index = stage.getCostumeIndexByName(stimulus.name);
        if (index < 0) return false;
        stage.setCostume(index);
        runtime.startHats('event_whenbackdropswitchesto', {BACKDROP: stimulus.name});
        return true;
      }
      case 'broadcast':
        runtime.startHats('event_whenbroadcastreceived', {BROADCAST_OPTION: stimulus.name});
        return true;
      default:
        return false;
    }
  }

  /** Lets go of every key still held (at the end of a run). */
  function releaseAll(vm, held) {
    for (const [key, timer] of held) {
      clearTimeout(timer);
      vm.postIOData('keyboard', {key: key, isDown: false});
    }
    held.clear();
  }

  /**
   * Answers each question asked, `delayMs` after it shows, with the next of `answers` (round and round;
   * none when the list is empty). `given` lists the answers given, in order, and `at` the frame each was
   * given at (`frameOf()`); `stop()` ends it.
   */
  function answerer(vm, answers, delayMs, frameOf) {
    const runtime = vm.runtime;
    const given = [];
    const at = [];
    let next = 0;
    let timer = null;
    const onQuestion = (question) => {
      clearTimeout(timer);
      timer = null;
      if (question === null || question === undefined || answers.length === 0) return; // cleared, or nothing to say
      timer = setTimeout(() => {
        timer = null;
        const answer = answers[next % answers.length];
        next += 1;
        given.push(answer);
        at.push(frameOf());
        runtime.emit('ANSWER', answer);
      }, delayMs);
    };
    runtime.on('QUESTION', onQuestion);
    return {
      given,
      at,
      stop() {
        clearTimeout(timer);
        runtime.removeListener('QUESTION', onQuestion);
      },
    };
  }

  return {KINDS, apply, releaseAll, answerer};
}});
