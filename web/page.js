// koma's page: pick or drop a file, POST it to /page/inspect (what it is) and /page/run (the
// CLI's command on it, server/page_routes.h), offer the files it writes for download, and show
// the report in the sandboxed frame /page/report-frame.html. No framework, nothing loaded
// from elsewhere.
(function () {
  'use strict';
  var COMMAND_TEXT = {
    skeletal: 'koma skeletal: omissions and holds',
    curves: 'koma curves: twos, threes, tame, tsume',
    lipblink: 'koma lipblink: mouths and blinks'
  };
  var file = null;       // the File picked
  var links = [];        // object URLs of the last result, revoked on the next
  var reportHtml = null; // the last report, handed to the frame once it is ready

  function $(id) { return document.getElementById(id); }

  function setStatus(text, isError) {
    $('status').textContent = text;
    $('status').className = isError ? 'error' : '';
  }

  function showFieldsets() {
    var command = $('command').value;
    document.querySelectorAll('fieldset[data-for]').forEach(function (set) {
      var on = set.dataset.for === command;
      set.hidden = !on;
      set.disabled = !on;
    });
  }

  function describe(info) {
    var about = $('about');
    about.textContent = '';
    function row(term, value) {
      var dt = document.createElement('dt');
      dt.textContent = term;
      var dd = document.createElement('dd');
      dd.textContent = value;
      about.append(dt, dd);
    }
    row('file', file.name + ' (' + info.bytes + ' bytes)');
    row('format', info.format_name || 'not a format koma reads');
    if (info.frames !== undefined) row('frames', String(info.frames));
    if (info.fps !== undefined) row('rate', (+info.fps.toFixed(3)) + ' fps');
    if (info.joints !== undefined) row('joints', String(info.joints));
    if (info.seconds !== undefined) row('length', info.seconds.toFixed(2) + ' s');
    if (info.sample_rate !== undefined) row('sample rate', info.sample_rate + ' Hz, ' + info.channels + ' channel(s)');
    if (info.animations) row('animations', info.animations.length ? info.animations.map(function (a) { return a || '(unnamed)'; }).join(', ') : 'none');
    if (info.curves) {
      var shown = info.curves.slice(0, 12).join(', ');
      row('curves', info.curves.length + ': ' + shown + (info.curves.length > 12 ? ', ...' : ''));
    }
    if (info.error) row('reading it', info.error);
    about.hidden = false;
  }

  function chooseCommands(info) {
    var select = $('command');
    select.textContent = '';
    (info.commands || []).forEach(function (c) {
      if (c.flag && c.flag !== '--audio') return;  // read only beside another file
      var option = document.createElement('option');
      option.value = c.command;
      option.textContent = COMMAND_TEXT[c.command] || c.command;
      select.append(option);
    });
    var any = select.options.length > 0;
    select.disabled = !any;
    $('run').disabled = !any;
    showFieldsets();
    return any;
  }

  function pick(picked) {
    if (!picked) return;
    file = picked;
    $('result').hidden = true;
    setStatus('Reading ' + file.name + ' ...');
    fetch('/page/inspect?name=' + encodeURIComponent(file.name), {method: 'POST', body: file})
      .then(function (r) { return r.json(); })
      .then(function (info) {
        describe(info);
        if (chooseCommands(info)) {
          setStatus(file.name + ': choose the timing and press Run (or Enter).');
          $('command').focus();
        } else {
          setStatus(file.name + ': koma reads no such file.', true);
        }
      })
      .catch(function (e) { setStatus('Could not read the file: ' + e, true); });
  }

  function bytesOf(base64) {
    var text = atob(base64);
    var bytes = new Uint8Array(text.length);
    for (var i = 0; i < text.length; i++) bytes[i] = text.charCodeAt(i);
    return bytes;
  }

  var TYPES = {result: 'application/octet-stream', timing: 'text/csv', xdts: 'application/octet-stream', report: 'text/html'};
  var LABELS = {result: 'the result', timing: 'the timing sheet (CSV)', xdts: 'the exposure sheet (XDTS)', report: 'the report (HTML)'};

  function showResult(answer) {
    links.forEach(function (url) { URL.revokeObjectURL(url); });
    links = [];
    $('command-line').textContent = answer.command;
    var list = $('downloads');
    list.textContent = '';
    reportHtml = null;
    answer.files.forEach(function (f) {
      var bytes = bytesOf(f.base64);
      var url = URL.createObjectURL(new Blob([bytes], {type: TYPES[f.role]}));
      links.push(url);
      var a = document.createElement('a');
      a.href = url;
      a.download = f.name;
      a.dataset.role = f.role;
      a.textContent = 'Download ' + LABELS[f.role] + ': ' + f.name;
      var item = document.createElement('li');
      item.append(a, ' (' + f.bytes + ' bytes)');
      list.append(item);
      if (f.role === 'report') reportHtml = new TextDecoder().decode(bytes);
    });
    $('result').hidden = false;
    var frame = $('report');
    frame.hidden = reportHtml === null;
    frame.dataset.shown = '';
    if (reportHtml !== null) frame.src = '/page/report-frame.html';
  }

  window.addEventListener('message', function (event) {
    var frame = $('report');
    if (event.source !== frame.contentWindow || !event.data) return;
    if (event.data.kind === 'koma-report-frame-ready' && reportHtml !== null) {
      frame.contentWindow.postMessage(reportHtml, '*');
    } else if (event.data.kind === 'koma-report-shown') {
      frame.dataset.shown = event.data.ready ? 'ready' : 'failed';
      frame.dataset.figures = String(event.data.figures);
      setStatus(event.data.ready ? 'Done: the report is below, the files to download above it.'
                                 : 'Done, but the report did not draw.', !event.data.ready);
    }
  });

  function run(event) {
    event.preventDefault();
    if (!file || $('run').disabled) return;
    var command = $('command').value;
    var query = ['command=' + encodeURIComponent(command), 'name=' + encodeURIComponent(file.name)];
    var fields = $('run-form').querySelectorAll('select[name], input[name]');
    fields.forEach(function (field) {
      if (field.name === 'command' || field.matches(':disabled') || field.value === '') return;
      query.push(encodeURIComponent(field.name) + '=' + encodeURIComponent(field.value));
    });
    $('run').disabled = true;
    setStatus('Running koma ' + command + ' on ' + file.name + ' ...');
    fetch('/page/run?' + query.join('&'), {method: 'POST', body: file})
      .then(function (r) { return r.json(); })
      .then(function (answer) {
        if (answer.error) throw new Error(answer.error.message);
        if (answer.exit_code !== 0) {
          var message = answer.summary && answer.summary.error ? answer.summary.error.message : answer.messages;
          // koma's message without its pointer to --help, which the page's fields replace.
          throw new Error(message.split('\n').filter(function (line) {
            return line && line.indexOf('Run `koma') !== 0;
          }).join(' '));
        }
        showResult(answer);
        setStatus('Done: drawing the report ...');
        $('downloads').querySelector('a').focus();
      })
      .catch(function (e) { setStatus(String(e.message || e), true); })
      .then(function () { $('run').disabled = false; });
  }

  document.addEventListener('DOMContentLoaded', function () {
    $('file').addEventListener('change', function () { pick(this.files[0]); });
    $('command').addEventListener('change', showFieldsets);
    $('run-form').addEventListener('submit', run);
    var drop = $('drop');
    ['dragenter', 'dragover'].forEach(function (name) {
      drop.addEventListener(name, function (e) { e.preventDefault(); drop.classList.add('over'); });
    });
    ['dragleave', 'drop'].forEach(function (name) {
      drop.addEventListener(name, function () { drop.classList.remove('over'); });
    });
    drop.addEventListener('drop', function (e) {
      e.preventDefault();
      if (e.dataTransfer.files.length) pick(e.dataTransfer.files[0]);
    });
    showFieldsets();
  });
})();
