// Compiles deploy/farm/koma-batch.js as flamenco-manager would (its JOB_TYPE and compileJob in
// a sandbox with `author` and the job), and prints each task's command as one line of JSON
// ({"name", "type", "exe", "args"}), for batch_shard_e2e_test.sh to run.
// Usage: node flamenco_compile.js JOB_TYPE_JS SETTINGS_JSON
"use strict";
const fs = require("fs");
const vm = require("vm");

const [jobTypePath, settingsJson] = process.argv.slice(2);
const tasks = [];
const author = {
  Task: (name, type) => {
    const task = {name, type, commands: [], addCommand(c) { this.commands.push(c); }};
    return task;
  },
  Command: (type, parameters) => ({type, parameters}),
};
const sandbox = {author, console};
vm.createContext(sandbox);
vm.runInContext(fs.readFileSync(jobTypePath, "utf8") + "\n;this.JOB_TYPE = JOB_TYPE;", sandbox,
                {filename: jobTypePath});

// Settings as the manager fills them: the given ones over JOB_TYPE's defaults; required ones
// must be there.
const given = JSON.parse(settingsJson);
const settings = {};
for (const s of sandbox.JOB_TYPE.settings) {
  if (s.key in given) settings[s.key] = given[s.key];
  else if ("default" in s) settings[s.key] = s.default;
  else if (s.required) throw new Error(`setting ${s.key} is required`);
  if (s.choices && !s.choices.includes(settings[s.key])) {
    throw new Error(`setting ${s.key}: ${settings[s.key]} is not one of ${s.choices}`);
  }
}
sandbox.compileJob({settings, addTask: (t) => tasks.push(t)});
for (const t of tasks) {
  if (t.commands.length !== 1 || t.commands[0].type !== "exec") {
    throw new Error(`task ${t.name}: want one exec command`);
  }
  const {exe, args} = t.commands[0].parameters;
  console.log(JSON.stringify({name: t.name, type: t.type, exe, args}));
}
