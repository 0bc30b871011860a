/*
 * The page's AudioContexts, suspended while no one can hear them.
 *
 * An editor holds three: the VM's audio engine (the project's sounds) and one per Blockly workspace
 * (the code area and the palette's flyout, for click sounds), all running from the start. A running
 * context costs ~0.01 of a core in silence (the renderer's and the audio service's audio threads), a
 * suspended one nothing; measured with 8 waiting editors on 2 cores, the three took half of what the
 * editors cost together.
 * - The VM's runs only while the page runs its project on the real clock: a page that waits (parked,
 *   recycled, or an episode's on the paused virtual clock) suspends it. Nothing the VM sees depends on
 *   it: sounds on the virtual clock end in virtual time (clock.js).
 * - The workspaces' never run: no one hears them and nothing reads them (a click played on a suspended
 *   context is simply not heard).
 * - Any other the page makes later runs as the VM's does. The GUI makes one on the page's first mouse
 *   or key gesture (for its sound editor and recorder) and keeps it to itself; recycling presses Escape,
 *   so before these were tracked every page that had served once held a running context for good: 0.02-0.03
 *   of a core each (renderer and audio service), and the node's cores went to silence as a sweep went on.
 *   Contexts are tracked from this script on (it runs before the GUI's bundle), through a subclass of
 *   `AudioContext`; one made while the VM's is held still is suspended as soon as its maker is done with
 *   it (the GUI's unlock helper would resume one found suspended, frame after frame).
 * The bridge takes `create` from `window.__scratchworldAudio` (and deletes it).
 */
(function () {
  'use strict';

  // Every AudioContext made from here on; `held` while the VM's context is to stand still.
  const made = new Set();
  let held = false;
  const NativeAudioContext = window.AudioContext;
  window.AudioContext = class AudioContext extends NativeAudioContext {
    constructor(...args) {
      super(...args);
      made.add(this);
      if (held) queueMicrotask(() => { if (held && this.state === 'running') this.suspend(); });
    }
  };

  // vm(): the VM or null; blocksComponent(): the GUI's Blocks component, throwing where there is none
  // (the bare page, or a workspace not drawn yet).
  function create(vm, blocksComponent) {
    function vmContext() {
      const engine = vm() && vm().runtime.audioEngine;
      return (engine && engine.audioContext) || null;
    }

    // Every workspace Blockly holds: the code area, the palette's flyout, a dialog's such as "Make a Block".
    function workspaceContexts() {
      let scratchBlocks;
      try {
        scratchBlocks = blocksComponent().ScratchBlocks;
      } catch (e) {
        return [];
      }
      return scratchBlocks.common.getAllWorkspaces()
        .map((workspace) => typeof workspace.getAudioManager === 'function' && workspace.getAudioManager().context)
        .filter(Boolean);
    }

    // Contexts made since this script ran that are neither the VM's nor a workspace's (closed ones forgotten).
    function otherContexts() {
      const known = new Set([vmContext(), ...workspaceContexts()]);
      for (const context of made) if (context.state === 'closed') made.delete(context);
      return [...made].filter((context) => !known.has(context));
    }

    // The VM's context, and any other the page made, running or suspended as `running` says; the workspaces'
    // suspended.
    async function set(running) {
      held = !running;
      const wanted = workspaceContexts().map((context) => [context, false]);
      for (const context of otherContexts()) wanted.push([context, running]);
      const ofVm = vmContext();
      if (ofVm) wanted.push([ofVm, running]);
      for (const [context, run] of wanted) {
        if (context.state === 'closed') continue;
        if (run && context.state !== 'running') await context.resume();
        if (!run && context.state === 'running') await context.suspend();
      }
    }

    return {vmContext: vmContext, workspaceContexts: workspaceContexts, otherContexts: otherContexts, set: set};
  }

  window.__scratchworldAudio = {create: create};
})();
