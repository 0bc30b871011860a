/*
 * The bare evaluation page's stage: Scratch's VM, renderer, storage, bitmap adapter and audio engine
 * wired together as the editor GUI wires them (its VM manager and Stage container), with no GUI.
 *
 * What the GUI does that a verdict can see is done here the same way: the VM in compatibility mode
 * (30 frames a second), an audio engine (sounds have lengths; "play until done" waits for them), the
 * renderer's canvas sized like the GUI's stage (small 240x180, large 480x360 at pixel ratio 1), and
 * real mouse events on the page posted to the VM as the Stage posts them (so `go to mouse-pointer`
 * knows the mouse only after a real move, as in the editor). What it leaves out (Blockly, React,
 * menus, monitors drawn as HTML, the ask prompt's text field) only shows the VM's state.
 */
(function () {
  'use strict';

  const stage = document.getElementById('stage');
  const canvas = document.createElement('canvas');
  stage.appendChild(canvas);

  const vm = new VirtualMachine();
  vm.attachStorage(new ScratchStorage.ScratchStorage()); // projects carry their assets; nothing is fetched
  const renderer = new ScratchRender(canvas);
  vm.attachRenderer(renderer);
  vm.attachV2BitmapAdapter(new ScratchSVGRenderer.BitmapAdapter());
  vm.attachAudioEngine(new AudioEngine());
  vm.setCompatibilityMode(true);
  vm.initialized = true;
  // Scratch's fonts, as the editor has them once its default project loaded: the first SVG costume
  // would otherwise add their style element to the page, and the page would no longer recycle clean.
  ScratchSVGRenderer.inlineSvgFonts('<svg xmlns="http://www.w3.org/2000/svg"/>');

  // The bridge asks for the GUI's stage sizes (small 240x180, large 480x360).
  function setSize(width, height) {
    stage.style.width = `${width}px`;
    stage.style.height = `${height}px`;
    renderer.resize(width, height);
    const rect = canvas.getBoundingClientRect();
    return {canvas: [canvas.width, canvas.height], stageRect: {x: rect.x, y: rect.y, width: rect.width, height: rect.height}};
  }

  // As the GUI's Stage: positions relative to the canvas, with its size, on every move and button change.
  function postMouse(event, isDown) {
    const rect = canvas.getBoundingClientRect();
    const data = {x: event.clientX - rect.left, y: event.clientY - rect.top, canvasWidth: rect.width, canvasHeight: rect.height};
    if (isDown !== undefined) data.isDown = isDown;
    vm.postIOData('mouse', data);
  }
  document.addEventListener('mousemove', (event) => postMouse(event));
  document.addEventListener('mouseup', (event) => postMouse(event, false));
  canvas.addEventListener('mousedown', (event) => postMouse(event, true));

  setSize(480, 360);
  scratchworld.attachStage({setSize: setSize});
  scratchworld.attachVm(vm);
  vm.start();
})();
