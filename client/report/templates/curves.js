// koma report, RetimeCurves: each curve before (smooth) and after (stepped) with the key
// poses and the drawings marked, the hold histogram, the drawing sheet.
(function curvesReport(D) {
  const grid = D.timing_fps > 0;
  const duration = (D.frames - 1) / D.fps;
  // Each timing group's key poses (seconds), and how many keyframe times each merges (1: none).
  const keysOf = (g) => (grid ? g.key_grid_frames.map((k) => k / D.timing_fps) : g.key_frames.map((k) => k / D.fps));
  const groupKeys = D.groups.map(keysOf);
  const merged = (g, i) => (D.groups[g].key_merged.length ? D.groups[g].key_merged[i] : 1);
  const mergedCount = D.groups.reduce((n, g, gi) => n + g.key_frames.filter((_, i) => merged(gi, i) > 1).length, 0);

  const curvesSection = section('Curves before and after');
  const cursors = [];  // a time cursor on every plot, following the player below the plots
  const keyCount = D.curves.reduce((n, c) => n + c.keys.length, 0);
  const sharedCount = D.curves.reduce((n, c) => n + c.keys.filter((k) => !k[2]).length, 0);
  curvesSection.append(legend([['var(--before)', 'before (input, smooth)'], ['var(--after)', 'after (drawings, stepped)'],
                               ['var(--key)', `key poses (${D.key_frames.length}` +
                                 (mergedCount ? `; solid: ${mergedCount} merged from several keyframe times)` : ')')],
                               ['var(--drawn-key)', `keys drawn exactly (◆ ${keyCount - sharedCount}` +
                                 (sharedCount ? `; ◇ ${sharedCount} shared a drawing and not drawn)` : ')')]]));
  // The curves that move first; the flat ones (the input never changes) in one line.
  const moving = (c) => { const [lo, hi] = range(c.before.y); return hi > lo; };
  const flat = D.curves.filter((c) => !moving(c));
  if (D.groups.length > 1) {
    curvesSection.append(el('p', {class: 'legend'}, 'Timing groups, each on its own key poses: ' +
      D.groups.map((g) => `${g.name} (${g.mode === 'step' ? '' : g.mode + ', '}${g.curves} curves, ${g.key_frames.length} key poses)`).join(', ') + '.'));
  }
  for (const c of D.curves.filter(moving)) {
    const timing = c.timing >= 0 ? D.timings[c.timing] : null;  // null: a kept curve
    const [lo1, hi1] = range(c.before.y), [lo2, hi2] = range(c.after.y);
    const plot = plotFrame({xMax: duration, yMin: Math.min(lo1, lo2), yMax: Math.max(hi1, hi2), height: 170});
    plot.svg.classList.add('curve-plot');
    plot.svg.dataset.curve = c.id;
    groupKeys[c.group].forEach((t, i) => {
      const attrs = {class: 'key', x1: plot.x(t), x2: plot.x(t), y1: plot.top, y2: plot.bottom};
      if (merged(c.group, i) > 1) {
        attrs.class = 'key merged';
        attrs['data-merged'] = merged(c.group, i);
      }
      plot.svg.append(svgEl('line', attrs));
    });
    plot.svg.append(svgEl('path', {class: 'before', d: pathOf(plot, c.before.x, c.before.y, false)}));
    plot.svg.append(svgEl('path', {class: 'after', d: pathOf(plot, c.after.x, c.after.y, c.timing >= 0, duration)}));
    // A dot where each drawing starts (its first grid frame, else its first output frame).
    const starts = !timing ? [] : grid ? timing.drawing_start_grid.map((g) => g / D.timing_fps) : timing.drawing_start.map((f) => f / D.fps);
    const dots = svgEl('g', {class: 'drawings'});
    if (starts.length <= 4000) {
      for (let j = 0; j < starts.length; ++j) {
        const t = starts[j];
        // The value the drawing shows: the stepped plot's value at its start.
        let v = c.after.y[0];
        for (let i = 0; i < c.after.x.length && c.after.x[i] <= t + 1e-9; ++i) v = c.after.y[i];
        dots.append(svgEl('circle', {class: 'drawing', cx: plot.x(t), cy: plot.y(v), r: 2.5, 'data-drawing': j}));
      }
    }
    plot.svg.append(dots);
    // The curve's keys koma draws (docs/semantics.md, "Every key is drawn"): a diamond at the
    // key, filled where a drawing shows it exactly, hollow where it shared a drawing; a key a
    // drawing early or late is joined to the drawing that shows it.
    const keyMarks = svgEl('g', {class: 'drawn-keys'});
    for (const [t, v, drawn, displaced, shownAt] of c.keys) {
      const x = plot.x(t), y = plot.y(v);
      if (displaced) keyMarks.append(svgEl('line', {class: 'key-link', x1: x, y1: y, x2: plot.x(shownAt), y2: y}));
      keyMarks.append(svgEl('path', {class: drawn ? 'keymark drawn' : 'keymark shared', d: `M${x} ${y - 4.5}L${x + 4.5} ${y}L${x} ${y + 4.5}L${x - 4.5} ${y}Z`,
                                     'data-time': t, 'data-value': v, 'data-drawn': drawn ? 1 : 0, 'data-shown-at': shownAt}));
    }
    plot.svg.append(keyMarks);
    const cursor = svgEl('line', {class: 'cursor', y1: plot.top, y2: plot.bottom});
    plot.svg.append(cursor);
    cursors.push({plot, line: cursor});
    const g = D.groups[c.group];
    const group = D.groups.length > 1 ? `${g.name}${g.mode === 'step' ? '' : ' (' + g.mode + ')'}, ` : '';
    const how = timing ? `on ${timing.n}s, ${starts.length} drawings` : 'kept as it is';
    const keyText = c.keys.length ? `, ${c.keys.filter((k) => k[2]).length} of ${c.keys.length} keys drawn` : '';
    curvesSection.append(el('h3', {'data-mode': g.mode}, `${c.id} — ${group}${how}${keyText}`), plot.svg);
  }
  if (flat.length) {
    curvesSection.append(el('p', {class: 'flat-curves', 'data-curves': JSON.stringify(flat.map((c) => c.id))},
      `${flat.length} curve${flat.length > 1 ? 's do' : ' does'} not move (not plotted): ${flat.map((c) => c.id).join(', ')}.`));
  }

  // ---- hold histograms ------------------------------------------------------------------------
  const histSection = section('Hold histogram (' + (grid ? 'holds in grid frames' : 'holds in frames') + ')');
  const seen = new Set();
  for (const first of D.curves) {
    if (first.timing < 0 || seen.has(first.timing)) continue;
    seen.add(first.timing);
    // Holds of a stepped curve of the timing (LipBlink's mouth and eyes have none of their own).
    const c = D.curves.find((o) => o.timing === first.timing && o.histogram.length) || first;
    const ids = D.curves.filter((o) => o.timing === c.timing).map((o) => o.id);
    const maxCount = Math.max(1, ...c.histogram.map((h) => h[1]));
    const width = 60 + 56 * c.histogram.length, height = 150, bottom = 120;
    const svg = svgEl('svg', {width, height, viewBox: `0 0 ${width} ${height}`, class: 'histogram', 'data-timing': c.timing});
    c.histogram.forEach(([length, count], i) => {
      const h = 100 * count / maxCount, x = 40 + 56 * i;
      svg.append(svgEl('rect', {x, y: bottom - h, width: 40, height: h, class: 'kind-H', 'data-length': length, 'data-drawings': count}));
      svg.append(svgEl('text', {x: x + 20, y: bottom - h - 4, 'text-anchor': 'middle'}, String(count)));
      svg.append(svgEl('text', {x: x + 20, y: bottom + 16, 'text-anchor': 'middle'}, length + 'f'));
    });
    histSection.append(el('h3', {}, `on ${D.timings[c.timing].n}s: ${ids.join(', ')}`), svg);
  }

  // ---- the drawing sheet ----------------------------------------------------------------------
  // Rows: grid frames with a film grid, else frames; one drawing column per timing.
  const rows = grid ? D.grid_count : D.frames;
  const drawingAt = D.timings.map((timing) => {
    const at = new Int32Array(rows);
    if (grid) {
      let j = 0;
      for (let g = 0; g < rows; ++g) {
        while (j + 1 < timing.drawing_start_grid.length && timing.drawing_start_grid[j + 1] <= g) ++j;
        at[g] = j;
      }
    } else {
      for (let f = 0; f < rows; ++f) at[f] = timing.drawing_of_frame[f];
    }
    return at;
  });
  // Per row: the groups with a key pose there ("body", "face ×3" for a pose merging three times).
  const keyRows = new Map();
  D.groups.forEach((g, gi) => (grid ? g.key_grid_frames : g.key_frames).forEach((k, i) => {
    const label = (D.groups.length > 1 ? g.name : 'KEY') + (merged(gi, i) > 1 ? ` ×${merged(gi, i)}` : '');
    keyRows.set(k, keyRows.has(k) ? `${keyRows.get(k)}, ${label}` : label);
  }));
  const columns = [grid ? 'grid frame' : 'frame', 'time', 'key pose'];
  if (grid) columns.push('source frames');
  // A timing's column names its group when there are several (one track per group).
  const groupOfTiming = D.timings.map((_, t) => {
    const c = D.curves.find((o) => o.timing === t);
    return c && D.groups.length > 1 ? D.groups[c.group].name + ' ' : '';
  });
  D.timings.forEach((timing, t) => columns.push(`${groupOfTiming[t]}drawing (on ${timing.n}s)`));
  const fixed = grid ? 4 : 3;
  const cell = (r, c) => {
    if (c === 0) return [String(r)];
    if (c === 1) return [(grid ? r / D.timing_fps : r / D.fps).toFixed(3)];
    if (c === 2) return keyRows.has(r) ? [keyRows.get(r), 'new'] : [''];
    if (grid && c === 3) {
      const first = D.grid_first_frame[r], next = r + 1 < rows ? D.grid_first_frame[r + 1] : D.frames;
      return [next - 1 > first ? `${first}–${next - 1}` : next - 1 === first ? String(first) : '–'];
    }
    const at = drawingAt[c - fixed];
    return drawingCell(r === 0 || at[r] !== at[r - 1], at[r] + 1);
  };
  const sheetSection = section('Drawing sheet');
  sheetSection.append(el('p', {class: 'legend'}, (grid ? `One row per frame of the ${D.timing_fps} fps film grid` : 'One row per frame') +
    '; a thick line every second. Each new drawing is numbered; | means it is held.'));
  const rowFps = grid ? D.timing_fps : D.fps;
  const sheet = makeSheet(rows, columns, cell, (r) => ({second: r > 0 && Math.abs(r / rowFps - Math.round(r / rowFps)) < 1e-9}));
  sheetSection.append(sheet.element);
  exposureSheetSection(D.xdts, rowFps);
  // ---- the player: scrub the curves' frames; the cursors and the sheet follow ------------------
  // Output frame t shows, per timing, drawing drawing_of_frame[t]; with a grid it lies in the
  // grid frame whose source frames (grid_first_frame) include it.
  const rowOfFrame = (t) => {
    if (!grid) return t;
    let lo = 0, hi = rows - 1;
    while (lo < hi) {
      const mid = (lo + hi + 1) >> 1;
      if (D.grid_first_frame[mid] <= t) lo = mid; else hi = mid - 1;
    }
    return lo;
  };
  const describe = (t) => {
    let text = `frame ${t} / ${D.frames - 1} · ${seconds(t / D.fps)}`;
    if (grid) text += ` · grid frame ${rowOfFrame(t)}`;
    return text + ' · ' + D.timings.map((timing) => `drawing ${timing.drawing_of_frame[t] + 1} on ${timing.n}s`).join(', ');
  };
  const player = makePlayer(D.frames, D.fps, (t) => {
    for (const c of cursors) {
      c.line.setAttribute('x1', c.plot.x(t / D.fps));
      c.line.setAttribute('x2', c.plot.x(t / D.fps));
    }
    sheet.highlight(rowOfFrame(t));
  }, describe);
  curvesSection.insertBefore(player.controls, curvesSection.children[2]);
  player.show(0);
  reportReady();
})(KOMA);
