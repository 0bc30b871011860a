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
 * The bridge takes `create` from `window.__scratchworldAudio` (and deletes it).
 */
(function () {
  'use strict';

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

    // The VM's context running or suspended, as `running` says; the workspaces' suspended.
    async function set(running) {
      const wanted = workspaceContexts().map((context) => [context, false]);
      const ofVm = vmContext();
      if (ofVm) wanted.push([ofVm, running]);
      for (const [context, run] of wanted) {
        if (context.state === 'closed') continue;
        if (run && context.state !== 'running') await context.resume();
        if (!run && context.state === 'running') await context.suspend();
      }
    }

    return {vmContext: vmContext, workspaceContexts: workspaceContexts, set: set};
  }

  window.__scratchworldAudio = {create: create};
})();
