// The page's solver: a module worker that instantiates the page's own WebAssembly module (sent,
// already compiled, as its first message) and hands every later message to lopin_web's
// solver_worker, with those that came while it was being instantiated.
import init, { solver_worker } from "./lopin_web.js";

const early = [];
let started = false;
self.onmessage = async (e) => {
  if (started) {
    early.push(e.data);
    return;
  }
  started = true;
  await init({ module_or_path: e.data });
  solver_worker(early);
};
