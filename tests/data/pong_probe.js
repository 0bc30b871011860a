// For upstream's pong_starter golden: the ball moves 15 steps a frame, bounces off the edges and
// stops the game when it touches the red line; with the paddle hidden its path has no randomness,
// so the game must stop after the same number of frames, at the same time, under either clock.
'use strict';

module.exports = async (vm) => {
  const runtime = vm.runtime;
  const paddle = runtime.targets.find((t) => t.isOriginal && t.getName() === 'Paddle');
  const ball = runtime.targets.find((t) => t.isOriginal && t.getName() === 'Ball');
  let frames = 0;
  const step = runtime._step;
  runtime._step = function () {
    frames += 1;
    return step.apply(this, arguments);
  };
  const started = Date.now();
  vm.greenFlag();
  paddle.setVisible(false);
  let moved = false;
  await new Promise((resolve) => {
    const poll = () => {
      if (ball.x !== 20 || ball.y !== 150) moved = true;
      if ((moved && runtime.threads.length === 0) || Date.now() - started > 8000) resolve();
      else setTimeout(poll, 5);
    };
    poll();
  });
  const took = Date.now() - started;
  runtime._step = step;
  const stopped = runtime.threads.length === 0;
  return {details: [
    {name: 'the ball moves', passed: moved},
    {name: 'the game stops when the ball reaches the red line', passed: stopped,
     meta: {took, frames, x: Math.round(ball.x), y: Math.round(ball.y)}},
  ]};
};
