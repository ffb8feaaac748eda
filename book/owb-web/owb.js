// The course book's interactive parts: answer fields under each exercise, each student's own
// exercise, and the playground. The work is done by the workbench compiled to WebAssembly
// (web/, built by web/build.sh into owb-web/); this script only reads fields, calls it and shows
// what it returns. Math is typeset by KaTeX, shipped with the book (katex/katex.min.js).
// Everything loads from the book's own folder: the module comes inlined in a classic script, so
// the book also works opened as a local file.
(function () {
  "use strict";

  var root = typeof path_to_root === "string" ? path_to_root : "";
  var loading = null;

  function script(src) {
    return new Promise(function (resolve, reject) {
      var s = document.createElement("script");
      s.src = root + src;
      s.onload = resolve;
      s.onerror = function () {
        reject(new Error("could not load " + src + " (build the book with web/build.sh first)"));
      };
      document.head.appendChild(s);
    });
  }

  function decode(base64) {
    var text = atob(base64);
    var bytes = new Uint8Array(text.length);
    for (var i = 0; i < text.length; i++) bytes[i] = text.charCodeAt(i);
    return bytes;
  }

  // ---- the workbench, in a Web Worker ---------------------------------------------------------

  // The module runs in a Web Worker, so a long computation never freezes the page: the worker is
  // made from a Blob (its source, wasm-bindgen's loader and a message loop, comes in a classic
  // script), which works from a static host and from file:// alike. The module itself is fetched
  // as a .wasm file and compiled while it streams in where the page is served; opened as a local
  // file, where browsers refuse to fetch, it comes inlined (base64) in a script instead. Where a
  // worker cannot be made, the module runs in the page as before.
  var worker = null;
  var moduleSource = null;
  var calls = {};
  var nextCall = 0;
  var api = null;

  function inlineModule() {
    return script("owb-web/owb_web_wasm.js").then(function () {
      return decode(window.OWB_WASM_BASE64);
    });
  }

  function fetchModule() {
    if (location.protocol !== "file:" && typeof WebAssembly.compileStreaming === "function") {
      return WebAssembly.compileStreaming(fetch(root + "owb-web/owb_web.wasm")).catch(inlineModule);
    }
    return inlineModule();
  }

  function settle(id, answer) {
    var call = calls[id];
    if (!call) return;
    delete calls[id];
    if ("error" in answer) call.reject(new Error(answer.error));
    else call.resolve(answer.ok);
  }

  function startWorker() {
    var url = URL.createObjectURL(new Blob([window.OWB_WORKER_SOURCE], { type: "text/javascript" }));
    var w = new Worker(url);
    w.onmessage = function (e) {
      // the worker says when its warm-up (one small design, see web/worker.js) is done
      if (e.data.warm !== undefined) {
        document.documentElement.setAttribute("data-owb-warm", String(e.data.warm));
        return;
      }
      settle(e.data.id, e.data);
    };
    w.onerror = function (e) {
      e.preventDefault();
      Object.keys(calls).forEach(function (id) { settle(id, { error: e.message || "the worker failed" }); });
    };
    return w;
  }

  function post(message) {
    return new Promise(function (resolve, reject) {
      nextCall += 1;
      calls[nextCall] = { resolve: resolve, reject: reject };
      message.id = nextCall;
      worker.postMessage(message);
    });
  }

  // Stops the running computation: the worker is dropped and a fresh one loads the module.
  function restart() {
    worker.terminate();
    Object.keys(calls).forEach(function (id) { settle(id, { error: "stopped" }); });
    worker = startWorker();
    loading = post({ init: moduleSource }).then(function () { return api; });
  }

  // Calls the module's function `fn`; past 0.2 s the status element says it is computing and
  // offers to stop.
  function callWorker(fn, args, status) {
    var result = post({ fn: fn, args: args });
    if (!status) return result;
    var timer = setTimeout(function () {
      status.textContent = "Computing… ";
      status.classList.remove("owb-error");
      var stop = el("button", "owb-stop", "Stop");
      stop.type = "button";
      stop.addEventListener("click", restart);
      status.appendChild(stop);
    }, 200);
    var done = function () { clearTimeout(timer); };
    return result.then(function (x) { done(); return x; }, function (e) { done(); throw e; });
  }

  // The workbench, loaded once per page: a promise of `{ call(fn, args, status) }`, whose calls
  // answer with the module's JSON text.
  function workbench() {
    if (!loading) {
      loading = Promise.all([
        script("owb-web/owb_web_worker.js"),
        script("katex/katex.min.js"),
        fetchModule(),
      ])
        .then(function (loaded) {
          moduleSource = loaded[2];
          try {
            worker = startWorker();
          } catch (e) {
            return inPage();
          }
          api = { call: callWorker };
          return post({ init: moduleSource }).then(function (version) {
            document.documentElement.setAttribute("data-owb-worker", "yes");
            return version;
          });
        })
        .then(function (version) {
          document.documentElement.setAttribute("data-owb-ready", version);
          return api;
        });
    }
    return loading;
  }

  // Without a worker: the module in the page (a compiled module or bytes, either loads).
  function inPage() {
    return script("owb-web/owb_web.js")
      .then(function () { return wasm_bindgen({ module_or_path: moduleSource }); })
      .then(function () {
        api = {
          call: function (fn, args) {
            return new Promise(function (resolve) { resolve(wasm_bindgen[fn].apply(null, args)); });
          },
        };
        return wasm_bindgen.version();
      });
  }

  // Runs f with the workbench once it is loaded. Before the module is there (a slow link, the
  // first use) the page says it is loading; if it cannot load or fails, the page says so
  // instead of doing nothing; a computation stopped by the reader says so.
  function withWorkbench(status, f) {
    if (status && !document.documentElement.hasAttribute("data-owb-ready")) {
      status.textContent = "Loading the workbench (the first time only)…";
    }
    return workbench().then(f).catch(function (e) {
      if (status) {
        var message = String((e && e.message) || e);
        status.textContent = message === "stopped"
          ? "Stopped."
          : "The workbench could not run here: " + message;
        status.classList.add("owb-error");
      }
    });
  }

  function el(tag, cls, text) {
    var e = document.createElement(tag);
    if (cls) e.className = cls;
    if (text !== undefined) e.textContent = text;
    return e;
  }

  function math(target, latex, display) {
    try {
      katex.render(latex, target, { displayMode: !!display, throwOnError: false });
    } catch (e) {
      target.textContent = latex;
    }
  }

  // A TOML basic string holding exactly s: every control character escaped, so that the
  // checker sees a pasted U+0007 and says so at its part (a TOML error would hide the part).
  function tomlString(s) {
    return '"' + s.replace(/[\\"\u0000-\u001f\u007f]/g, function (c) {
      if (c === "\\") return "\\\\";
      if (c === '"') return '\\"';
      return "\\u" + ("000" + c.charCodeAt(0).toString(16).toUpperCase()).slice(-4);
    }) + '"';
  }

  function shellWord(s) {
    return /^[A-Za-z0-9_.,+\-\/=:]+$/.test(s) ? s : '"' + s.replace(/(["\\$`])/g, "\\$1") + '"';
  }

  // ---- exercises -------------------------------------------------------------------------

  // The answers typed so far, as the answer file `owb check` reads.
  function answerFile(form, student) {
    var lines = ["exercise = " + tomlString(form.getAttribute("data-exercise-id"))];
    if (student) lines.push("student = " + tomlString(student));
    lines.push("", "[answers]");
    form.querySelectorAll(".owb-part").forEach(function (part) {
      // no-break and figure spaces (pasted from a PDF) are spaces; other invisible characters
      // go to the checker, which names them and their column
      var value = part.querySelector(".owb-answer").value.replace(/[\u00a0\u2007\u202f]/g, " ").trim();
      if (value) lines.push(part.getAttribute("data-part") + " = " + tomlString(value));
    });
    return lines.join("\n") + "\n";
  }

  function showFeedback(part, result, read) {
    var box = part.querySelector(".owb-feedback");
    var readBox = part.querySelector(".owb-read");
    box.textContent = "";
    readBox.textContent = "";
    box.className = "owb-feedback";
    if (!result) return;
    box.classList.add(result.verdict === "correct" ? "owb-correct" : "owb-wrong");
    var head = el("div", "owb-verdict");
    var words = {
      correct: "✔ correct",
      wrong: "✘ not right",
      missing: "✘ no answer",
      unreadable: "✘ cannot be read",
    }[result.verdict];
    head.textContent = words + " (" + result.score + "/" + result.points + ")";
    // the feedback's first line names the mistake in words; its key is kept for scripts
    if (result.mistake) box.setAttribute("data-mistake", result.mistake);
    else box.removeAttribute("data-mistake");
    box.appendChild(head);
    box.appendChild(el("div", "owb-feedback-text", result.feedback));
    if (read) {
      readBox.appendChild(el("span", "owb-read-label", "read as "));
      var m = el("span");
      math(m, read, false);
      readBox.appendChild(m);
    }
  }

  function check(form, exerciseToml, student) {
    var score = form.querySelector(".owb-score");
    var file = answerFile(form, student);
    if (!document.documentElement.hasAttribute("data-owb-ready")) {
      score.textContent = "Loading the workbench (the first time only)…";
    }
    var started = performance.now();
    return workbench().then(function (owb) {
      started = performance.now();
      return owb.call("check", [exerciseToml, file], score);
    }).then(function (text) {
      var out = JSON.parse(text);
      form.querySelectorAll(".owb-part").forEach(function (part) {
        var id = part.getAttribute("data-part");
        var answered = part.querySelector(".owb-answer").value.trim() !== "";
        var result = out.report && answered
          ? out.report.parts.find(function (p) { return p.id === id; })
          : null;
        showFeedback(part, result, out.read && out.read[id]);
      });
      if (out.error) {
        score.textContent = out.error;
        score.className = "owb-score owb-error";
      } else {
        var answered = out.report.parts.filter(function (p) { return p.verdict !== "missing"; });
        score.className = "owb-score";
        score.textContent = "score " + out.report.score + " / " + out.report.points +
          " (" + answered.length + " of " + out.report.parts.length + " parts answered)";
      }
      form.setAttribute("data-check-ms", (performance.now() - started).toFixed(1));
      form.setAttribute("data-checked", String(Number(form.getAttribute("data-checked") || 0) + 1));
      return out;
    }).catch(function (e) {
      var message = String(e.message || e);
      score.textContent = message === "stopped" ? "Stopped." : message;
      score.className = "owb-score owb-error";
    });
  }

  // Answers are kept in the browser (localStorage), per exercise, student and part, so a reload,
  // a chapter link or Back loses nothing; where storage is refused (a private window, file://
  // in some browsers) the page works as before.
  // keyed by book (its folder: two courses on one host keep apart), exercise, student and part
  var bookKey = new URL(root || "./", location.href).pathname;
  function storageKey(form, student, part) {
    return "owb-answer:" + bookKey + ":" + form.getAttribute("data-exercise-id") + ":" + (student || "") + ":" + part;
  }
  function stored(key) {
    try { return window.localStorage.getItem(key); } catch (e) { return null; }
  }
  function store(key, value) {
    try {
      if (value) window.localStorage.setItem(key, value);
      else window.localStorage.removeItem(key);
    } catch (e) { /* storage refused: nothing kept */ }
  }

  function wireExercise(form, exerciseToml, student) {
    var fileBox = form.querySelector(".owb-answer-toml");
    var refresh = function () {
      if (fileBox) fileBox.textContent = answerFile(form, student);
    };
    form.querySelectorAll(".owb-part").forEach(function (part) {
      var input = part.querySelector(".owb-answer");
      var key = storageKey(form, student, part.getAttribute("data-part"));
      var kept = stored(key);
      if (kept !== null && input.value === "") input.value = kept;
      input.addEventListener("input", function () { store(key, input.value); });
    });
    refresh();
    form.querySelectorAll(".owb-answer").forEach(function (input) {
      input.addEventListener("input", refresh);
      input.addEventListener("keydown", function (ev) {
        if (ev.key === "Enter") {
          ev.preventDefault();
          check(form, exerciseToml, student);
        }
      });
    });
    form.querySelector(".owb-check").addEventListener("click", function () {
      check(form, exerciseToml, student);
    });
    fileButtons(form, exerciseToml, student, refresh);
    // answers kept from an earlier visit come back with their feedback
    var restored = Array.prototype.some.call(form.querySelectorAll(".owb-answer"), function (input) {
      return input.value.trim() !== "";
    });
    if (restored) workbench().then(function () { check(form, exerciseToml, student); });
  }

  // The answers of a part from an answer file (`[answers]`, one `part = "text"` per line, TOML
  // basic strings): part → text.
  function readAnswerFile(text) {
    var answers = {};
    var inAnswers = false;
    text.split(/\r?\n/).forEach(function (line) {
      var t = line.trim();
      if (/^\[.*\]$/.test(t)) {
        inAnswers = t === "[answers]";
        return;
      }
      var m = /^("[^"]*"|[A-Za-z0-9_-]+)\s*=\s*"((?:[^"\\]|\\.)*)"\s*(#.*)?$/.exec(t);
      if (!inAnswers || !m) return;
      try {
        answers[m[1].replace(/^"|"$/g, "")] = JSON.parse('"' + m[2] + '"');
      } catch (e) { /* an escape JSON does not know: the part is left as it is */ }
    });
    return answers;
  }

  // "Save my answers" (the file `owb check` reads), "Load answers" (such a file back into the
  // fields, then checked) and "Clear my answers" (fields, feedback and what the browser kept).
  function fileButtons(form, exerciseToml, student, refresh) {
    var actions = form.querySelector(".owb-actions");
    if (!actions || actions.querySelector(".owb-clear")) return;
    var button = function (cls, text) {
      var b = el("button", cls, text);
      b.type = "button";
      actions.appendChild(document.createTextNode(" "));
      actions.appendChild(b);
      return b;
    };
    if (!actions.querySelector(".owb-download")) {
      button("owb-download", "Save my answers").addEventListener("click", function () {
        var blob = new Blob([answerFile(form, student)], { type: "text/plain" });
        var a = document.createElement("a");
        a.href = URL.createObjectURL(blob);
        a.download = form.getAttribute("data-exercise-id") + ".toml";
        document.body.appendChild(a);
        a.click();
        a.remove();
      });
    }
    var picker = el("input", "owb-load-file");
    picker.type = "file";
    picker.accept = ".toml,text/plain";
    picker.hidden = true;
    picker.setAttribute("aria-label", "an answer file to load");
    actions.appendChild(picker);
    button("owb-load", "Load answers").addEventListener("click", function () { picker.click(); });
    picker.addEventListener("change", function () {
      var file = picker.files && picker.files[0];
      if (!file) return;
      file.text().then(function (text) {
        var answers = readAnswerFile(text);
        form.querySelectorAll(".owb-part").forEach(function (part) {
          var id = part.getAttribute("data-part");
          var input = part.querySelector(".owb-answer");
          input.value = answers[id] || "";
          store(storageKey(form, student, id), input.value);
        });
        picker.value = "";
        refresh();
        check(form, exerciseToml, student);
      });
    });
    button("owb-clear", "Clear my answers").addEventListener("click", function () {
      form.querySelectorAll(".owb-part").forEach(function (part) {
        part.querySelector(".owb-answer").value = "";
        store(storageKey(form, student, part.getAttribute("data-part")), "");
        showFeedback(part, null, null);
      });
      var score = form.querySelector(".owb-score");
      score.textContent = "";
      score.className = "owb-score";
      refresh();
    });
  }

  // ---- each student's own exercise ---------------------------------------------------------

  function paragraphs(target, text) {
    text.trim().split(/\n\s*\n/).forEach(function (block) {
      var p = el("p");
      block.split(/(\*\*[^*]+\*\*)/).forEach(function (piece) {
        if (/^\*\*[^*]+\*\*$/.test(piece)) p.appendChild(el("strong", null, piece.slice(2, -2)));
        else p.appendChild(document.createTextNode(piece));
      });
      target.appendChild(p);
    });
  }

  // A statement as the workbench lays it out: paragraphs, numbered steps, the system typeset.
  function statementBlocks(target, blocks) {
    blocks.forEach(function (b) {
      if (b.text !== undefined) {
        paragraphs(target, b.text);
      } else if (b.steps) {
        var list = el("ol", "owb-steps");
        b.steps.forEach(function (step) { list.appendChild(el("li", null, step)); });
        target.appendChild(list);
      } else if (b.math !== undefined) {
        var box = el("div", "owb-math");
        box.setAttribute("tabindex", "0");
        math(box, b.math, true);
        target.appendChild(box);
      }
    });
  }

  // The method each part asks for (not its answer), as the book's exercises show it.
  function hints(parts) {
    var list = el("ul");
    parts.forEach(function (p) {
      if (!p.hint) return;
      var item = el("li");
      item.appendChild(el("code", null, p.id));
      item.appendChild(document.createTextNode(": " + p.hint));
      list.appendChild(item);
    });
    var details = el("details", "owb-hints");
    details.appendChild(el("summary", null, "Hints"));
    details.appendChild(list);
    return list.children.length ? details : null;
  }

  function variantExercise(v, student) {
    var form = el("div", "owb-exercise");
    form.setAttribute("data-exercise-id", v.id);
    v.parts.forEach(function (p) {
      var part = el("div", "owb-part");
      part.setAttribute("data-part", p.id);
      var label = el("label");
      var input = el("input", "owb-answer");
      input.type = "text";
      input.id = "owb-" + v.id + "-" + p.id;
      input.spellcheck = false;
      input.autocomplete = "off";
      label.htmlFor = input.id;
      label.appendChild(el("code", null, p.id));
      label.appendChild(document.createTextNode(" — " + p.prompt + " "));
      label.appendChild(el("span", "owb-points", "(" + p.points + " point" + (p.points === 1 ? "" : "s") + ")"));
      part.appendChild(label);
      part.appendChild(input);
      part.appendChild(el("div", "owb-read"));
      var feedback = el("div", "owb-feedback");
      feedback.setAttribute("aria-live", "polite");
      part.appendChild(feedback);
      form.appendChild(part);
    });
    var hinted = hints(v.parts);
    if (hinted) form.appendChild(hinted);
    var actions = el("div", "owb-actions");
    var button = el("button", "owb-check", "Check");
    button.type = "button";
    actions.appendChild(button);
    actions.appendChild(document.createTextNode(" "));
    actions.appendChild(el("span", "owb-score"));
    var save = el("button", "owb-download", "Save my answers");
    save.type = "button";
    actions.appendChild(document.createTextNode(" "));
    actions.appendChild(save);
    form.appendChild(actions);
    var details = el("details", "owb-answer-file");
    details.appendChild(el("summary", null, "Your answers as a file (hand this in)"));
    var pre = el("pre");
    pre.appendChild(el("code", "owb-answer-toml"));
    details.appendChild(pre);
    form.appendChild(details);
    save.addEventListener("click", function () {
      var blob = new Blob([answerFile(form, student)], { type: "text/plain" });
      var a = document.createElement("a");
      a.href = URL.createObjectURL(blob);
      a.download = v.id + "-" + student.replace(/[^A-Za-z0-9_-]/g, "_") + ".toml";
      document.body.appendChild(a);
      a.click();
      a.remove();
    });
    wireExercise(form, v.toml, student);
    return form;
  }

  function wireVariant(box) {
    var body = box.querySelector(".owb-variant-body");
    box.querySelector(".owb-new-variant").addEventListener("click", function () {
      var student = box.querySelector(".owb-student").value.trim();
      var order = box.querySelector(".owb-order").value;
      var convention = box.querySelector(".owb-convention").value;
      var kind = box.querySelector(".owb-kind").value;
      withWorkbench(body, function (owb) {
        return owb.call("variant", [student, order, convention, kind], body);
      }).then(function (text) {
        if (text === undefined) return;
        var v = JSON.parse(text);
        body.textContent = "";
        if (v.error) {
          body.appendChild(el("p", "owb-error", v.error));
          return;
        }
        body.appendChild(el("h4", null, v.title));
        statementBlocks(body, v.statement_blocks);
        var p = el("p", "owb-note");
        p.appendChild(document.createTextNode("Exercise "));
        p.appendChild(el("code", null, v.id));
        p.appendChild(document.createTextNode(". Your teacher regenerates it with "));
        p.appendChild(el("code", null, v.command));
        p.appendChild(document.createTextNode(" and grades the saved answers with "));
        p.appendChild(el("code", null, "owb grade variants SUBMISSIONS/ --csv report.csv"));
        p.appendChild(document.createTextNode("."));
        body.appendChild(p);
        body.appendChild(variantExercise(v, student));
        box.setAttribute("data-variant", v.id);
      });
    });
  }

  // ---- the playground -----------------------------------------------------------------------

  // keys whose values are numbers in a request (the others are text in the workbench's syntax)
  var NUMBER_KEYS = ["output", "starts", "seed", "grid", "time-limit", "tolerance",
    "derivative-output", "derivative-state"];

  // `key = value` lines as a request: {"command": …, key: value}; `true` for a flag
  function requestOf(command, text) {
    var request = { command: command };
    text.split("\n").forEach(function (line) {
      var at = line.indexOf("=");
      if (line.trim() === "" || at < 0) return;
      var key = line.slice(0, at).trim().replace(/^--/, "");
      var value = line.slice(at + 1).trim();
      if (value === "true") request[key] = true;
      else if (NUMBER_KEYS.indexOf(key) >= 0 && value !== "" && !isNaN(Number(value))) request[key] = Number(value);
      else request[key] = value;
    });
    return request;
  }

  function wordsOf(request) {
    var words = [request.command];
    Object.keys(request).forEach(function (key) {
      if (key === "command") return;
      words.push("--" + key);
      if (request[key] !== true) words.push(String(request[key]));
    });
    return words;
  }

  // Derivations longer than this are typeset on request: KaTeX runs on the page's thread, and a
  // 30-state derivation took it a quarter of a second (measured in the browser test).
  var TYPESET_AT_ONCE = 20000;

  function showRun(out, parts) {
    parts.math.textContent = "";
    if (out.latex && out.latex.length <= TYPESET_AT_ONCE) {
      math(parts.math, out.latex, true);
    } else if (out.latex) {
      var typeset = el("button", "owb-typeset", "Typeset the derivation (" + Math.round(out.latex.length / 1000) + " thousand characters of LaTeX)");
      typeset.type = "button";
      typeset.addEventListener("click", function () {
        parts.math.textContent = "";
        math(parts.math, out.latex, true);
      });
      parts.math.appendChild(typeset);
    }
    parts.output.className = parts.outputClass + (out.status === 2 || out.error ? " owb-error" : "");
    var text = out.output || "";
    if (out.error) {
      text += "error: " + out.error + "\n";
      (out.causes || []).forEach(function (c) { text += "  caused by: " + c + "\n"; });
    }
    parts.output.textContent = text;
  }

  function wireAnyCommand(box) {
    var select = box.querySelector(".owb-any-command");
    if (!select) return;
    var fields = box.querySelector(".owb-any-fields");
    var fill = function () {
      var option = select.options[select.selectedIndex];
      if (option) fields.value = option.getAttribute("data-fields");
    };
    select.addEventListener("change", fill);
    fill();
    box.querySelector(".owb-any-run").addEventListener("click", function () {
      var request = requestOf(select.value, fields.value);
      var started = performance.now();
      withWorkbench(box.querySelector(".owb-any-output"), function (owb) {
        started = performance.now();
        return owb.call("run", [JSON.stringify(request)], box.querySelector(".owb-any-output"));
      }).then(function (text) {
        if (text === undefined) return;
        var out = JSON.parse(text);
        box.querySelector(".owb-any-command-line").textContent = "owb " + wordsOf(request).map(shellWord).join(" ");
        showRun(out, {
          math: box.querySelector(".owb-any-math"),
          output: box.querySelector(".owb-any-output"),
          outputClass: "owb-any-output",
        });
        box.setAttribute("data-any-ms", (performance.now() - started).toFixed(1));
        box.setAttribute("data-any-ran", String(Number(box.getAttribute("data-any-ran") || 0) + 1));
      });
    });
  }

  function wirePlayground(box) {
    var value = function (cls) { return box.querySelector(cls).value.trim(); };
    var command = box.querySelector(".owb-command");
    var mathBox = box.querySelector(".owb-math");
    var output = box.querySelector(".owb-output");
    box.querySelectorAll("button[data-run]").forEach(function (button) {
      button.addEventListener("click", function () {
        // the request, keys named as the command line's flags; the page shows the command
        // line that makes the same request
        var request = { command: button.getAttribute("data-run"), a: value(".owb-a"), c: value(".owb-c") };
        if (request.command === "gain") {
          request[value(".owb-family")] = value(".owb-desired");
          request.method = value(".owb-method");
          request.convention = value(".owb-pconvention");
          if (box.querySelector(".owb-float").checked) request.float = true;
        }
        var started = performance.now();
        withWorkbench(output, function (owb) {
          started = performance.now();
          return owb.call("run", [JSON.stringify(request)], output);
        }).then(function (text) {
          if (text === undefined) return;
          var out = JSON.parse(text);
          command.textContent = "owb " + wordsOf(request).map(shellWord).join(" ");
          showRun(out, { math: mathBox, output: output, outputClass: "owb-output" });
          box.setAttribute("data-run-ms", (performance.now() - started).toFixed(1));
          box.setAttribute("data-ran", String(Number(box.getAttribute("data-ran") || 0) + 1));
        });
      });
    });
    wireAnyCommand(box);
    var select = box.querySelector(".owb-example");
    var source = box.querySelector(".owb-example-toml");
    var fill = function () {
      var option = select.options[select.selectedIndex];
      if (option) source.value = option.getAttribute("data-toml");
    };
    select.addEventListener("change", fill);
    fill();
    box.querySelector(".owb-verify").addEventListener("click", function () {
      var result = box.querySelector(".owb-verify-output");
      withWorkbench(result, function (owb) {
        return owb.call("verify", [select.value, source.value], result);
      }).then(function (text) {
        if (text === undefined) return;
        var out = JSON.parse(text);
        result.className = "owb-verify-output" + (out.error ? " owb-error" : "");
        result.textContent = out.error ? "error: " + out.error : out.text;
        box.setAttribute("data-verified", String(Number(box.getAttribute("data-verified") || 0) + 1));
      });
    });
  }

  // ---- for keyboards and screen readers ------------------------------------------------------

  // What the book's template leaves to fix (axe-core runs over every page in the browser
  // test): the sidebar toggle is a label that acts as a button; the "on this page" outline
  // nests lists without list items; code boxes that scroll must take the focus, or a keyboard
  // cannot scroll them; and a skip link leads past the sidebar to the exercise or the text.
  function accessible() {
    var toggle = document.getElementById("mdbook-sidebar-toggle");
    if (toggle && !toggle.hasAttribute("role")) {
      toggle.setAttribute("role", "button");
      toggle.setAttribute("tabindex", "0");
      toggle.addEventListener("keydown", function (ev) {
        if (ev.key === "Enter" || ev.key === " ") {
          ev.preventDefault();
          toggle.click();
        }
      });
    }
    document.querySelectorAll(".on-this-page ol > ol, .on-this-page ul > ol").forEach(function (list) {
      var item = document.createElement("li");
      list.parentNode.insertBefore(item, list);
      item.appendChild(list);
    });
    document.querySelectorAll("pre > code, pre.owb-output, pre.owb-verify-output, pre.owb-any-output, figure.owb-figure, .table-wrapper, .katex-display, .owb-math, .owb-any-math").forEach(function (box) {
      var scrolls = box.scrollWidth > box.clientWidth + 1 || box.scrollHeight > box.clientHeight + 1;
      if (scrolls && !box.hasAttribute("tabindex")) box.setAttribute("tabindex", "0");
    });
    if (!document.querySelector(".owb-skip")) {
      var target = document.querySelector(".owb-exercise, .owb-variant, .owb-playground") || document.querySelector("main");
      if (target) {
        if (!target.id) target.id = "owb-skip-target";
        if (!target.hasAttribute("tabindex")) target.setAttribute("tabindex", "-1");
        var skip = el("a", "owb-skip", target.tagName === "MAIN" ? "Skip to the text" : "Skip to the exercise");
        skip.href = "#" + target.id;
        document.body.insertBefore(skip, document.body.firstChild);
      }
    }
  }

  function start() {
    accessible();
    // the outline and the code boxes' widths are final once the page has loaded
    window.addEventListener("load", accessible);
    window.addEventListener("resize", accessible);
    var forms = document.querySelectorAll(".owb-exercise[data-exercise]");
    var variants = document.querySelectorAll(".owb-variant");
    var playgrounds = document.querySelectorAll(".owb-playground");
    forms.forEach(function (form) { wireExercise(form, form.getAttribute("data-exercise"), null); });
    variants.forEach(wireVariant);
    playgrounds.forEach(wirePlayground);
    // load ahead, so the first click answers at once
    if (forms.length + variants.length + playgrounds.length > 0) {
      workbench().catch(function (e) { console.error(e); });
    }
  }

  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", start);
  else start();
})();
