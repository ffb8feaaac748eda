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
      setTimeout(warmUp, 0);
    }, failed);
    return;
  }
  try {
    answer({ ok: wasm_bindgen[m.fn].apply(null, m.args) });
  } catch (err) {
    failed(err);
  }
};

// Once loaded, one exact 16-state gain (about 60 ms, here in the worker): the browser compiles a
// module first with a quick baseline compiler and optimises a function only once it has run a
// while, so without this the reader's first command ran two to three times slower than the
// next (a 30-state gain: 120 ms cold, 45 ms warm, in Node's V8). A command sent meanwhile
// waits for it.
function warmUp() {
  var n = 16, x = 3;
  var next = function () { x = (x * 1103515245 + 12345) % 2147483648; return (x % 19) - 9; };
  var rows = [];
  for (var i = 0; i < n; i++) {
    var row = [];
    for (var j = 0; j < n; j++) row.push(next());
    rows.push(row.join(" "));
  }
  var c = [], poles = [];
  for (var k = 0; k < n; k++) { c.push(next()); poles.push(-(k + 1)); }
  var start = Date.now();
  try {
    wasm_bindgen.run(JSON.stringify({
      command: "gain", a: "[" + rows.join("; ") + "]", c: "[" + c.join(" ") + "]",
      poles: poles.join(", "), summary: true,
    }));
  } catch (err) {
    // a warm-up that fails changes nothing the reader asked for
  }
  self.postMessage({ warm: Date.now() - start });
}
