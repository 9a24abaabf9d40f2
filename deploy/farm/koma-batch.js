// A Flamenco (v3) job type: `koma batch` split into N tasks, task K running
//   koma batch RPC CLIPS -o OUTPUT --server SERVER --shard K/N --summary OUTPUT/summary.json ...
// so that the N tasks, on any workers, together retime every clip once (each task its own
// manifest and summary, OUTPUT/.koma-batch.K-of-N.json and OUTPUT/summary.K-of-N.json). A
// task that fails and is requeued skips the clips it already finished.
// Install: copy this file into the `scripts` folder beside flamenco-manager and restart it;
// submit from a script or the web API with the settings below. docs/operations.md,
// "On a render farm". tests/e2e/batch_shard_e2e_test.sh compiles it and runs its commands.

const JOB_TYPE = {
  label: "koma batch",
  description: "Retime a folder of clips with koma, split into tasks",
  settings: [
    {key: "rpc", type: "string", choices: ["skeletal", "curves", "lipblink"], default: "skeletal",
     required: true, description: "koma batch's RPC"},
    {key: "clips", type: "string", subtype: "dir_path", required: true,
     description: "clips: a folder (searched by extension), a file, or @LIST"},
    {key: "output", type: "string", subtype: "dir_path", required: true,
     description: "output folder, shared by every task"},
    {key: "server", type: "string", default: "127.0.0.1:50051", required: true,
     description: "koma_server address(es): host:port,host:port or dns:///name:port"},
    {key: "tasks", type: "int32", default: 8, required: true,
     description: "tasks the batch is split into (1..1000000)"},
    {key: "koma", type: "string", default: "koma", description: "the koma client on the workers"},
    {key: "extra_args", type: "string", default: "",
     description: "more koma batch options, separated by spaces (--omit 6 --timing)"},
  ],
};

// The arguments of task `k` of `n` (exported for the test harness; Flamenco calls compileJob).
function komaBatchArgs(settings, k, n) {
  const extra = settings.extra_args ? settings.extra_args.split(" ").filter((a) => a.length > 0) : [];
  return ["batch", settings.rpc, settings.clips, "-o", settings.output, "--server", settings.server,
          "--shard", `${k}/${n}`, "--summary", `${settings.output}/summary.json`, "--quiet"]
      .concat(extra);
}

function compileJob(job) {
  const settings = job.settings;
  const n = settings.tasks;
  if (!Number.isInteger(n) || n < 1 || n > 1000000) {
    throw `tasks: ${n} must be a whole number from 1 to 1000000`;
  }
  for (let k = 0; k < n; k++) {
    const task = author.Task(`koma-batch-${k}-of-${n}`, "misc");
    task.addCommand(author.Command("exec", {exe: settings.koma || "koma",
                                            args: komaBatchArgs(settings, k, n)}));
    job.addTask(task);
  }
}
