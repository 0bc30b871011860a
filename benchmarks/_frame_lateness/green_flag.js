// The calibration's "evaluation script": runs the project from the green flag for `config.seconds` on
// the page's clock (real or virtual) while the page traces every VM frame (benchmarks/frame_lateness.py).
module.exports = async (vm, config) => {
  vm.greenFlag();
  await new Promise((resolve) => setTimeout(resolve, config.seconds * 1000));
  return {seconds: config.seconds};
};
