// Stand-in for an upstream script we do not have: passes when the project loaded with a sprite.
module.exports = async (vm) => ({
  details: [{name: 'project has a sprite', passed: vm.runtime.targets.some(t => t.isOriginal && !t.isStage)}],
});
