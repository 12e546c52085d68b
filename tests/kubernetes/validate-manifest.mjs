// Checks a foldcast Indexed Job manifest (docs/scale-out/foldcast-indexed-job.yaml) against the
// Kubernetes API schema, without a cluster:
//   node tests/kubernetes/validate-manifest.mjs MANIFEST.yaml   # exit 0 valid, 1 invalid
//   node tests/kubernetes/validate-manifest.mjs --self-test MANIFEST.yaml
//   node tests/kubernetes/validate-manifest.mjs --print-command MANIFEST.yaml   # the container's argv
// 1. JSON Schema of batch/v1 Job from the Kubernetes OpenAPI (kubernetes-models, ajv): types,
//    enumerations, required fields, formats (quantities such as "4Gi").
// 2. Unknown fields, which the API server refuses (kubectl's default --validate=strict) and a
//    JSON Schema without additionalProperties lets through: the manifest as a TypeScript object
//    literal of type Job (kubernetes-types), whose excess-property check names each stray key.
// 3. What foldcast needs of it: an Indexed Job whose completions equal the N of every
//    `--shard "${JOB_COMPLETION_INDEX}/N"` in its command, and `--threads` no more than the
//    container's CPU limit.
// --self-test first breaks the manifest in ways each check must catch, then checks it as is.
import { readFileSync } from "node:fs";
import path from "node:path";
import { fileURLToPath } from "node:url";
import ts from "typescript";
import { parseAllDocuments } from "yaml";
import { Job } from "kubernetes-models/batch/v1/Job";

const here = path.dirname(fileURLToPath(import.meta.url));

function schemaErrors(doc) {
  try {
    new Job(doc).validate();
    return [];
  } catch (e) {
    return [`Kubernetes schema: ${e.message}`];
  }
}

// Each manifest as `const jobK: Job = {...}` in one virtual file beside node_modules (one
// TypeScript program for all: building one takes seconds); returns the errors of each.
function unknownFieldErrors(docs) {
  const file = path.join(here, "manifest-check.ts");
  let source = `import type { Job } from "kubernetes-types/batch/v1";\n`;
  const starts = [];
  docs.forEach((doc, k) => {
    starts.push(source.length);
    source += `export const job${k}: Job = ${JSON.stringify(doc, null, 2)};\n`;
  });
  const options = {
    strict: true, noEmit: true, skipLibCheck: true, types: [], lib: ["lib.es5.d.ts"],
    module: ts.ModuleKind.CommonJS, moduleResolution: ts.ModuleResolutionKind.Node10,
  };
  const host = ts.createCompilerHost(options);
  const readFile = host.readFile.bind(host);
  const getSourceFile = host.getSourceFile.bind(host);
  host.fileExists = (name) => name === file || ts.sys.fileExists(name);
  host.readFile = (name) => (name === file ? source : readFile(name));
  host.getSourceFile = (name, version, ...rest) =>
    name === file ? ts.createSourceFile(name, source, version) : getSourceFile(name, version, ...rest);
  const program = ts.createProgram([file], options, host);
  const errors = docs.map(() => []);
  for (const d of ts.getPreEmitDiagnostics(program)) {
    // JSON's quoted keys: '"workdir"' reads 'workdir'.
    const message = ts.flattenDiagnosticMessageText(d.messageText, " ").replace(/'"([^"']*)"'/g, "'$1'");
    const text = `Kubernetes types: ${message}`;
    let k = starts.length - 1;
    while (k > 0 && (d.start ?? 0) < starts[k]) --k;
    if (d.file?.fileName === file && (d.start ?? 0) >= starts[0]) errors[k].push(text);
    else errors.forEach((e) => e.push(text));  // the import or the library itself: every manifest
  }
  return errors;
}

function foldcastErrors(doc) {
  const errors = [];
  const spec = doc?.spec ?? {};
  if (spec.completionMode !== "Indexed")
    errors.push("foldcast: spec.completionMode must be Indexed (JOB_COMPLETION_INDEX is the shard)");
  for (const container of spec.template?.spec?.containers ?? []) {
    const command = [...(container.command ?? []), ...(container.args ?? [])].join(" ");
    const name = `foldcast: container ${container.name}`;
    const shard = /--shard\s+"?\$\{?JOB_COMPLETION_INDEX\}?\/(\d+)"?/g;
    const shards = [...command.matchAll(shard)].map((m) => Number(m[1]));
    if (shards.length === 0) errors.push(`${name} runs no --shard "\${JOB_COMPLETION_INDEX}/N"`);
    for (const n of shards)
      if (n !== spec.completions) errors.push(`${name} splits into ${n} shards but spec.completions is ${spec.completions}`);
    const threads = command.match(/--threads\s+(\d+)/);
    const limit = String(container.resources?.limits?.cpu ?? "Infinity");  // "4", "3500m"
    const cpus = limit.endsWith("m") ? Number.parseFloat(limit) / 1000 : Number(limit);
    if (threads && Number(threads[1]) > cpus)
      errors.push(`foldcast: container ${container.name} renders with ${threads[1]} threads under a limit of ${cpus} CPUs`);
  }
  return errors;
}

// The errors of each manifest (a list of YAML documents).
function check(manifests) {
  const jobs = manifests.flat();
  const typeErrors = unknownFieldErrors(jobs);
  let next = 0;
  return manifests.map((docs) => {
    if (docs.length === 0) return ["no YAML document"];
    return docs.flatMap((doc, i) => {
      const types = typeErrors[next++];
      if (doc?.apiVersion !== "batch/v1" || doc?.kind !== "Job")
        return [`document ${i + 1}: apiVersion batch/v1, kind Job expected, not ${doc?.apiVersion} ${doc?.kind}`];
      return [...schemaErrors(doc), ...types, ...foldcastErrors(doc)];
    });
  });
}

function load(file) {
  const docs = parseAllDocuments(readFileSync(file, "utf8"));
  for (const d of docs) if (d.errors.length) throw new Error(`${file}: ${d.errors[0].message}`);
  return docs.map((d) => d.toJS());
}

// Each way of breaking the manifest, with the words its error must contain.
const container = (job) => job.spec.template.spec.containers[0];
const breakages = [
  ["completionMode misspelt", (j) => { j.spec.completionMode = "Indexd"; }, "completionMode"],
  ["completions as a string", (j) => { j.spec.completions = "8"; }, "completions must be integer"],
  ["a memory limit that is no quantity", (j) => { container(j).resources.limits.memory = "4 GB"; }, "memory"],
  ["a restartPolicy Kubernetes does not have", (j) => { j.spec.template.spec.restartPolicy = "Sometimes"; },
    "restartPolicy"],
  ["an unknown key", (j) => { j.spec.backofLimitPerIndex = 2; },
    "'backofLimitPerIndex' does not exist in type 'JobSpec'"],
  ["a key at the wrong level", (j) => { container(j).workdir = "/work"; },
    "'workdir' does not exist in type 'Container'"],
  ["N differs from completions", (j) => { j.spec.completions = 4; }, "splits into 8 shards but spec.completions is 4"],
  ["more threads than CPUs", (j) => { container(j).resources.limits.cpu = "2"; }, "4 threads under a limit of 2 CPUs"],
];

const args = process.argv.slice(2);
const selfTest = args[0] === "--self-test";
const printCommand = args[0] === "--print-command";
const file = selfTest || printCommand ? args[1] : args[0];
if (!file) {
  console.error("usage: node validate-manifest.mjs [--self-test | --print-command] MANIFEST.yaml");
  process.exit(2);
}
const docs = load(file);
if (printCommand) {
  // The first container's command and args, one a line, for run-pods.sh.
  const container = docs[0].spec.template.spec.containers[0];
  console.log([...(container.command ?? []), ...(container.args ?? [])].join("\n"));
  process.exit(0);
}
const variants = selfTest ? breakages.map(([, breakIt]) => {
  const broken = structuredClone(docs);
  breakIt(broken[0]);
  return broken;
}) : [];
const results = check([...variants, docs]);
let failed = false;
breakages.slice(0, variants.length).forEach(([what, , expected], k) => {
  const caught = results[k].some((e) => e.includes(expected));
  const detail = caught ? "" : ` (errors: ${results[k].join("; ") || "none"})`;
  console.log(`${caught ? "caught" : "MISSED"}: ${what}${detail}`);
  failed ||= !caught;
});
const errors = results[results.length - 1];
for (const e of errors) console.error(`${file}: ${e}`);
if (errors.length === 0)
  console.log(`${file}: valid batch/v1 Job (schema of kubernetes-models 4.5.1, fields of kubernetes-types 1.30.0), ` +
    `${docs[0].spec.completions} indexed shards`);
process.exit(failed || errors.length ? 1 : 0);
