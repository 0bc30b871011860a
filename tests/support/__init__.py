"""What tests share that is not a test: project and suite builders, run directories, the CLI runner, sweep
drivers, a local OpenAI-compatible server, loopback listeners, and the bad-input catalog's cases."""
