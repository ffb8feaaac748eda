// The message loop of the workbench's Web Worker (appended to wasm-bindgen's loader by
// web/build.sh): {init: module or bytes} loads the module and answers its version; {fn, args}
// calls an exported function and answers its JSON text. Every message carries an id, echoed.
self.onmessage = function (e) {
  var m = e.data;
  var answer = function (reply) {
    reply.id = m.id;
    self.postMessage(reply);
  };
  var failed = function (err) {
    answer({ error: String((err && err.message) || err) });
  };
  if (m.init) {
    wasm_bindgen({ module_or_path: m.init }).then(function () {
      answer({ ok: wasm_bindgen.version() });
    }, failed);
    return;
  }
  try {
    answer({ ok: wasm_bindgen[m.fn].apply(null, m.args) });
  } catch (err) {
    failed(err);
  }
};
