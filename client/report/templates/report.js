// koma report: what every report page shares. The data is the JSON in #koma-data, written by
// the koma client (client/report/); <kind>.js draws that report's figures with these helpers.
'use strict';

const KOMA = JSON.parse(document.getElementById('koma-data').textContent);
const SVG_NS = 'http://www.w3.org/2000/svg';

// An HTML element: el('p', {class: 'x'}, 'text', child, ...).
function el(tag, attrs, ...children) {
  const node = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) node.setAttribute(k, v);
  for (const c of children) node.append(c);
  return node;
}

// An SVG element, same shape.
function svgEl(tag, attrs, ...children) {
  const node = document.createElementNS(SVG_NS, tag);
  for (const [k, v] of Object.entries(attrs || {})) node.setAttribute(k, v);
  for (const c of children) node.append(c);
  return node;
}

function section(title, ...children) {
  const s = el('section', {}, el('h2', {}, title), ...children);
  document.getElementById('report').append(s);
  return s;
}

function seconds(t) { return t.toFixed(3) + ' s'; }

function legend(items) {
  return el('p', {class: 'legend'}, ...items.map(([color, text]) =>
    el('span', {}, el('span', {class: 'swatch', style: 'background:' + color}), text)));
}

// The header: input, options, counts, version.
function renderHeader(h) {
  const header = document.getElementById('header');
  header.append(el('p', {class: 'muted'}, h.rpc + ' · koma ' + h.version));
  const facts = (rows) => el('dl', {class: 'facts'}, ...rows.flatMap(([k, v]) =>
    [el('dt', {}, k), el('dd', {}, String(v))]));
  header.append(facts(h.format ? [['input', h.input], ['format', h.format]] : [['input', h.input]]));
  // Where the input file bent a rule and was read anyway (a BVH with more frames than its
  // Frames: line): said before anything else.
  for (const warning of h.warnings || []) {
    header.append(el('p', {class: 'warning'}, 'Warning: ' + warning));
  }
  header.append(el('h3', {}, 'Options'), facts(h.options));
  header.append(el('h3', {}, 'Counts'), facts(h.counts));
}

// A plot on a time axis in seconds. opts: {width, height, xMax, yMin, yMax}. Returns
// {svg, x(seconds) -> px, y(value) -> px, top, bottom, left, right}.
function plotFrame(opts) {
  const width = opts.width || 1100, height = opts.height || 180;
  const left = 56, right = width - 12, top = 10, bottom = height - 22;
  let yMin = opts.yMin, yMax = opts.yMax;
  if (!(yMax > yMin)) { yMax = yMin + 1; }
  const xMax = opts.xMax > 0 ? opts.xMax : 1;
  const x = (t) => left + (right - left) * t / xMax;
  const y = (v) => bottom - (bottom - top) * (v - yMin) / (yMax - yMin);
  const svg = svgEl('svg', {width, height, viewBox: `0 0 ${width} ${height}`, role: 'img'});
  svg.append(svgEl('line', {class: 'axis', x1: left, x2: right, y1: bottom, y2: bottom}));
  svg.append(svgEl('line', {class: 'axis', x1: left, x2: left, y1: top, y2: bottom}));
  const ticks = niceTicks(xMax, 10);
  for (const t of ticks) {
    svg.append(svgEl('line', {class: 'axis', x1: x(t), x2: x(t), y1: bottom, y2: bottom + 4}));
    svg.append(svgEl('text', {x: x(t), y: height - 6, 'text-anchor': 'middle'}, t.toFixed(t < 10 && xMax < 20 ? 1 : 0) + ' s'));
  }
  if (opts.yLabels !== false) {
    svg.append(svgEl('text', {x: left - 4, y: top + 9, 'text-anchor': 'end'}, fmt(yMax)));
    svg.append(svgEl('text', {x: left - 4, y: bottom, 'text-anchor': 'end'}, fmt(yMin)));
  }
  return {svg, x, y, top, bottom, left, right};
}

function fmt(v) { return Math.abs(v) >= 1000 || (v !== 0 && Math.abs(v) < 0.01) ? v.toExponential(1) : String(+v.toFixed(2)); }

function niceTicks(max, count) {
  const raw = max / count;
  const p = Math.pow(10, Math.floor(Math.log10(raw)));
  const step = [1, 2, 5, 10].map((m) => m * p).find((s) => s >= raw) || raw;
  const ticks = [];
  for (let t = 0; t <= max + 1e-9 && ticks.length < 50; t += step) ticks.push(t);
  return ticks;
}

// A polyline through (x[i], y[i]); stepped: hold each value until the next x.
function pathOf(plot, xs, ys, stepped, xEnd) {
  const parts = [];
  for (let i = 0; i < xs.length; ++i) {
    const px = plot.x(xs[i]).toFixed(1), py = plot.y(ys[i]).toFixed(1);
    if (i === 0) parts.push('M' + px + ' ' + py);
    else if (stepped) parts.push('H' + px + 'V' + py);
    else parts.push('L' + px + ' ' + py);
  }
  if (stepped && xs.length > 0 && xEnd !== undefined) parts.push('H' + plot.x(xEnd).toFixed(1));
  return parts.join('');
}

function range(values) {
  let lo = Infinity, hi = -Infinity;
  for (const v of values) { if (v < lo) lo = v; if (v > hi) hi = v; }
  return lo <= hi ? [lo, hi] : [0, 1];
}

// Reverses PackQuantised (client/report/report_data.cc): base64 -> varints -> zigzag deltas
// per value of a frame -> multiples of `step`. Returns a Float64Array of count values.
function unpackPositions(base64, count, perFrame, step) {
  const bin = atob(base64);
  const out = new Float64Array(count);
  const last = new Float64Array(perFrame);
  let pos = 0;
  for (let i = 0; i < count; ++i) {
    let v = 0, scale = 1, b;
    do {
      b = bin.charCodeAt(pos++);
      v += (b & 0x7f) * scale;
      scale *= 128;
    } while (b & 0x80);
    const delta = v % 2 === 0 ? v / 2 : -(v + 1) / 2;
    const k = i % perFrame;
    last[k] += delta;
    out[i] = last[k] * step;
  }
  return out;
}

// The player: play/pause at `fps` in real time, step, scrub. onFrame(t) draws frame t.
function makePlayer(frames, fps, onFrame, describe) {
  let frame = 0, playing = false, startMs = 0, startFrame = 0;
  const counter = el('span', {id: 'counter'});
  const scrub = el('input', {type: 'range', min: 0, max: frames - 1, value: 0, step: 1, id: 'scrubber', 'aria-label': 'frame'});
  const play = el('button', {type: 'button', id: 'play'}, 'Play');
  const back = el('button', {type: 'button', id: 'step-back', title: 'previous frame (←)'}, '◀ frame');
  const next = el('button', {type: 'button', id: 'step-forward', title: 'next frame (→)'}, 'frame ▶');
  const show = (t) => {
    frame = Math.max(0, Math.min(frames - 1, t));
    scrub.value = frame;
    counter.textContent = describe(frame);
    document.body.dataset.frame = frame;
    onFrame(frame);
  };
  const tick = (now) => {
    if (!playing) return;
    const t = startFrame + Math.floor((now - startMs) * fps / 1000);
    if (t >= frames) { show(frames - 1); setPlaying(false); return; }
    if (t !== frame) show(t);
    requestAnimationFrame(tick);
  };
  const setPlaying = (on) => {
    playing = on;
    play.textContent = on ? 'Pause' : 'Play';
    if (on) {
      if (frame >= frames - 1) show(0);
      startMs = performance.now(); startFrame = frame;
      requestAnimationFrame(tick);
    }
  };
  play.addEventListener('click', () => setPlaying(!playing));
  back.addEventListener('click', () => { setPlaying(false); show(frame - 1); });
  next.addEventListener('click', () => { setPlaying(false); show(frame + 1); });
  scrub.addEventListener('input', () => { setPlaying(false); show(+scrub.value); });
  document.addEventListener('keydown', (e) => {
    // A focused control already handles its own keys (the scrubber its arrows, a button Space).
    if (e.target instanceof HTMLInputElement || e.target instanceof HTMLButtonElement) return;
    if (e.key === 'ArrowRight') next.click();
    else if (e.key === 'ArrowLeft') back.click();
    else if (e.key === ' ') { e.preventDefault(); play.click(); }
  });
  const controls = el('div', {class: 'controls'}, play, back, next, scrub, counter);
  return {controls, show, frame: () => frame};
}

// An exposure sheet shown a page at a time: 144 rows = 6 s at 24 fps, the page of a Japanese
// timesheet. columns: header names; cell(r, c) -> [text, class]; rowInfo(r) -> {second: bool}.
function makeSheet(rows, columns, cell, rowInfo, pageSize, id) {
  pageSize = pageSize || 144;
  id = id || 'sheet';  // the table's id; its page controls are id-page, id-prev, id-next
  const pages = Math.max(1, Math.ceil(rows / pageSize));
  let page = -1, current = -1;
  const table = el('table', {class: 'sheet', id, 'data-rows': rows});
  const head = el('tr', {}, ...columns.map((c) => el('th', {}, c)));
  const body = el('tbody');
  table.append(el('thead', {}, head), body);
  const label = el('span', {id: id + '-page'});
  const prev = el('button', {type: 'button', id: id + '-prev'}, '◀ page');
  const nextPage = el('button', {type: 'button', id: id + '-next'}, 'page ▶');
  const render = (p) => {
    page = Math.max(0, Math.min(pages - 1, p));
    body.replaceChildren();
    const end = Math.min(rows, (page + 1) * pageSize);
    for (let r = page * pageSize; r < end; ++r) {
      const info = rowInfo(r);
      const tr = el('tr', {'data-row': r});
      if (info.second) tr.classList.add('second');
      if (r === current) tr.classList.add('current');
      for (let c = 0; c < columns.length; ++c) {
        const [text, cls] = cell(r, c);
        tr.append(cls ? el('td', {class: cls}, text) : el('td', {}, text));
      }
      body.append(tr);
    }
    label.textContent = `page ${page + 1} of ${pages} (rows ${page * pageSize}–${end - 1})`;
  };
  prev.addEventListener('click', () => render(page - 1));
  nextPage.addEventListener('click', () => render(page + 1));
  const highlight = (r) => {
    current = r;
    const p = Math.floor(r / pageSize);
    if (p !== page) render(p);
    for (const tr of body.querySelectorAll('tr.current')) tr.classList.remove('current');
    const row = body.querySelector(`tr[data-row="${r}"]`);
    if (row) {
      row.classList.add('current');
      // Keep the row in view inside the sheet's own scroll box (never scroll the page).
      if (row.offsetTop < wrap.scrollTop + 24 || row.offsetTop > wrap.scrollTop + wrap.clientHeight - 24) {
        wrap.scrollTop = row.offsetTop - wrap.clientHeight / 2;
      }
    }
  };
  const wrap = el('div', {class: 'sheet-wrap'}, table);
  render(0);
  return {element: el('div', {}, el('div', {class: 'sheet-pages'}, prev, nextPage, label), wrap), highlight, pages};
}

// Drawing numbers as an animator writes them: the number where a new drawing starts, a
// vertical stroke while it is held.
function drawingCell(isNew, number) {
  return isNew ? [String(number), 'new'] : ['|', 'hold'];
}

// The exposure sheet `--xdts` writes (docs/formats.md, XDTS): one row per sheet row, a column
// per Cell track (the drawing number where it changes, | while held, × for an empty cell) and
// per Dialog track (speaker: text on a line's first row, | after). `rowFps` marks seconds.
// Returns the sheet (its highlight(row) follows a player), or null without one.
function exposureSheetSection(X, rowFps) {
  if (!X || X.error !== undefined) return null;
  const s = section('Exposure sheet (XDTS)');
  s.append(el('p', {class: 'legend'},
    `The sheet --xdts writes for CLIP STUDIO PAINT, OpenToonz, Tahoma2D and TVPaint ("${X.name}", ${X.rows} rows): ` +
    'a column per layer (Cell track) numbering its drawings, | while a drawing is held; dialog columns give the speech.'));
  // Per track, per row: [text, class].
  const columns = X.tracks.map((t) => {
    const out = new Array(X.rows);
    for (let k = 0; k < t.changes.length; ++k) {
      const [row, cell] = t.changes[k];
      const end = k + 1 < t.changes.length ? t.changes[k + 1][0] : X.rows;
      for (let r = row; r < end; ++r) {
        out[r] = cell === '' ? ['×', 'empty'] : r === row ? [cell, 'new'] : ['|', 'hold'];
      }
    }
    return out;
  });
  const dialog = X.dialog.map((d) => {
    const out = new Array(X.rows).fill(null);
    for (const [b, e, speaker, text] of d.lines) {
      for (let r = b; r < e && r < X.rows; ++r) out[r] = r === b ? [speaker + ': ' + text, 'new'] : ['|', 'hold'];
    }
    return out;
  });
  const names = ['frame', ...X.tracks.map((t) => t.name), ...X.dialog.map((d) => d.name)];
  const cell = (r, c) => {
    if (c === 0) return [String(r)];
    if (c <= columns.length) return columns[c - 1][r];
    return dialog[c - 1 - columns.length][r] || [''];
  };
  const sheet = makeSheet(X.rows, names, cell,
    (r) => ({second: r > 0 && Math.abs(r / rowFps - Math.round(r / rowFps)) < 1e-9}), 144, 'xdts-sheet');
  s.append(sheet.element);
  return sheet;
}

// Called by <kind>.js when every figure is drawn (tests wait for data-ready="1").
function reportReady() { document.body.dataset.ready = '1'; }

renderHeader(KOMA.header);
