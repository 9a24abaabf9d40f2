// koma report, RetimeSkeletal: the stick figure before and after, the input's SSD curve with
// the omitted and hidden frames, the output's kinds, the X-sheet.
(function skeletalReport(D) {
  const framesOut = D.source_frames.length;
  const grid = D.timing_fps > 0;
  const KIND_NAME = {O: 'ORIGINAL', D: 'DUPLICATE', H: 'HELD'};
  const joints = D.joints.parents.length;

  // ---- the player ---------------------------------------------------------------------
  const playerSection = section('Before and after');
  const pose = D.pose;
  let positions = null;
  if (pose && pose.data !== undefined) {
    positions = unpackPositions(pose.data, D.frames_in * joints * pose.dims, joints * pose.dims, pose.step);
  } else {
    playerSection.append(el('p', {}, 'No figure: ' + (pose ? pose.error : 'no positions')));
  }
  // Views: through the camera (normalised device x, y), else orthographic front (x, y) and
  // side (z, y), y up as in BVH.
  const views = !positions ? [] : pose.camera ? [{name: 'camera', h: 0, v: 1}]
      : [{name: 'front', h: 0, v: 1}, {name: 'side', h: 2, v: 1}];
  const dims = pose ? pose.dims : 3;
  for (const view of views) {
    // The whole clip's extent, and the body's around its root (joint 0).
    let hLo = Infinity, hHi = -Infinity, vLo = Infinity, vHi = -Infinity, rLo = Infinity, rHi = -Infinity;
    for (let i = 0; i < positions.length; i += dims) {
      const h = positions[i + view.h], v = positions[i + view.v];
      if (h < hLo) hLo = h; if (h > hHi) hHi = h;
      if (v < vLo) vLo = v; if (v > vHi) vHi = v;
      const root = i - (i / dims % joints) * dims;
      const rel = h - positions[root + view.h];
      if (rel < rLo) rLo = rel; if (rel > rHi) rHi = rel;
    }
    const body = Math.max(rHi - rLo, vHi - vLo, 1e-9);
    const pad = 0.05 * body;
    // A figure that travels far (a walk) is followed: the view keeps the body's width and
    // moves with the root, and ticks on the ground show the travel.
    view.follow = hHi - hLo > 2.5 * Math.max(rHi - rLo, 0.3 * body);
    view.rel = [rLo - pad, rHi - rLo + 2 * pad];
    view.box = view.follow ? [hLo - pad, vLo - pad, rHi - rLo + 2 * pad, vHi - vLo + 2 * pad]
                           : [hLo - pad, vLo - pad, hHi - hLo + 2 * pad, vHi - vLo + 2 * pad];
    view.ground = vLo;
    view.span = [hLo - pad, hHi + pad];
    view.tick = niceTicks(body, 4)[1] || body;
  }
  const viewSize = views.length === 1 ? 520 : 260;
  // One <path> per view and side: "M parent L joint" for every bone; a ground line (y of the
  // lowest joint over the clip) under it.
  const makeFigure = (cls) => views.map((view) => {
    const [x, y, w, h] = view.box;
    const scale = Math.min(viewSize / w, 360 / h);
    const path = svgEl('path', {class: cls + ' figure', 'data-view': view.name, 'vector-effect': 'non-scaling-stroke'});
    const ground = svgEl('g', {class: 'floor'});
    ground.append(svgEl('line', {class: 'floor', x1: view.span[0], x2: view.span[1], y1: view.ground, y2: view.ground, 'vector-effect': 'non-scaling-stroke'}));
    if (view.follow) {
      const first = Math.ceil(view.span[0] / view.tick);
      for (let k = first; k * view.tick <= view.span[1] && k - first < 5000; ++k) {
        ground.append(svgEl('line', {class: 'floor', x1: k * view.tick, x2: k * view.tick, y1: view.ground, y2: view.ground - 0.03 * h, 'vector-effect': 'non-scaling-stroke'}));
      }
    }
    // SVG y grows downward: flip the vertical axis.
    // The onion skin: the input's pose at the same time, faint, under the retimed figure.
    const ghost = svgEl('path', {class: 'ghost', 'vector-effect': 'non-scaling-stroke'});
    const g = svgEl('g', {transform: `scale(1,-1) translate(0,${-(2 * y + h)})`}, ground, ghost, path);
    const svg = svgEl('svg', {width: Math.round(w * scale), height: Math.round(h * scale), viewBox: `${x} ${y} ${w} ${h}`,
                              'aria-label': view.name + ' view', 'data-follow': view.follow ? 1 : 0}, g);
    return {svg, path, ghost, view};
  });
  const bonesOf = (frame, view) => {
    const base = frame * joints * dims, parts = [];
    for (let j = 0; j < joints; ++j) {
      const p = D.joints.parents[j];
      if (p < 0) continue;
      const a = base + p * dims, b = base + j * dims;
      parts.push('M' + positions[a + view.h].toPrecision(6) + ' ' + positions[a + view.v].toPrecision(6) +
                 'L' + positions[b + view.h].toPrecision(6) + ' ' + positions[b + view.v].toPrecision(6));
    }
    return parts.join('');
  };
  const drawGhost = (figure, frame) => {
    for (const {ghost, view} of figure) ghost.setAttribute('d', frame === null ? '' : bonesOf(frame, view));
  };
  const drawPose = (figure, sourceFrame) => {
    const base = sourceFrame * joints * dims;
    for (const {svg, path, view} of figure) {
      const parts = [];
      for (let j = 0; j < joints; ++j) {
        const p = D.joints.parents[j];
        if (p < 0) continue;
        const a = base + p * dims, b = base + j * dims;
        parts.push('M' + positions[a + view.h].toPrecision(6) + ' ' + positions[a + view.v].toPrecision(6) +
                   'L' + positions[b + view.h].toPrecision(6) + ' ' + positions[b + view.v].toPrecision(6));
      }
      path.setAttribute('d', parts.join(''));
      path.setAttribute('data-source-frame', sourceFrame);
      if (view.follow) {
        const [, y, w, h] = view.box;
        svg.setAttribute('viewBox', `${(positions[base + view.h] + view.rel[0]).toPrecision(6)} ${y} ${w} ${h}`);
      }
    }
  };
  const VIEW_NAME = {front: 'front (x, y)', side: 'side (z, y)', camera: 'through the camera'};
  const viewWithName = (f) => el('div', {}, f.svg, el('div', {class: 'legend'}, VIEW_NAME[f.view.name]));
  const before = makeFigure('bone-before'), after = makeFigure('bone-after');
  const onion = el('input', {type: 'checkbox', id: 'onion', checked: ''});
  const beforeCaption = el('figcaption', {}, 'Before (input, ' + D.fps_in + ' fps)');
  const afterCaption = el('figcaption', {}, 'After (koma, ' + D.fps_out + ' fps)');
  const beforeLabel = el('div', {class: 'muted', id: 'before-label'});
  const afterLabel = el('div', {class: 'muted', id: 'after-label'});
  playerSection.append(el('div', {class: 'player'},
    el('figure', {id: 'before'}, beforeCaption, el('div', {class: 'views'}, ...before.map(viewWithName)), beforeLabel),
    el('figure', {id: 'after'}, afterCaption, el('div', {class: 'views'}, ...after.map(viewWithName)), afterLabel)));
  if (views.length > 1) playerSection.append(el('p', {class: 'legend'}, 'Orthographic views, y up as in BVH.'));

  // Input frame shown at output frame t's time (the rates differ with --output-rate timing).
  const inputFrameAt = (t) => Math.min(D.frames_in - 1, Math.floor(t * D.frame_time_out / D.frame_time_in + 1e-6));
  const describe = (t) => {
    let text = `frame ${t} / ${framesOut - 1} · ${seconds(t * D.frame_time_out)}`;
    if (grid) text += ` · grid frame ${D.grid_frames[t]}`;
    return text;
  };
  let sheet = null;
  const cursors = [];
  const onFrame = (t) => {
    const input = inputFrameAt(t), source = D.source_frames[t];
    if (positions) {
      drawPose(before, input);
      drawPose(after, source);
      drawGhost(after, onion.checked ? input : null);
    }
    beforeLabel.textContent = `source frame ${input}`;
    afterLabel.textContent = `drawing ${drawingOfFrame[t]} · source frame ${source} · ${KIND_NAME[D.kinds[t]]}`;
    const time = t * D.frame_time_out;
    for (const c of cursors) c.line.setAttribute('x1', c.plot.x(time)), c.line.setAttribute('x2', c.plot.x(time));
    if (sheet) sheet.highlight(grid ? D.grid_frames[t] : t);
  };
  // Drawing numbers over the output frames: a new one wherever the source frame changes.
  const drawingOfFrame = new Int32Array(framesOut);
  for (let t = 0, d = 0; t < framesOut; ++t) {
    if (t === 0 || D.source_frames[t] !== D.source_frames[t - 1]) ++d;
    drawingOfFrame[t] = d;
  }
  const player = makePlayer(framesOut, D.fps_out, onFrame, describe);
  playerSection.append(player.controls);
  if (positions) {
    onion.addEventListener('change', () => player.show(player.frame()));
    playerSection.append(el('label', {class: 'legend'}, onion,
      ' onion skin: the input at the same time, faint blue, behind the retimed figure (holds lag behind it, omissions jump ahead)'));
  }

  // ---- SSD with omitted and hidden frames; the output's kinds -----------------------------
  const duration = Math.max(D.frames_in * D.frame_time_in, framesOut * D.frame_time_out);
  const ssdSection = section('Speed of the input (SSD between consecutive ' + (grid ? 'grid frames' : 'frames') + ')');
  ssdSection.append(legend([['var(--before)', 'input SSD'], ['var(--omitted)', `omitted frames (${D.deleted.length})`],
                            ['var(--held)', `frames hidden by holds (${D.hidden.length})`],
                            ...(D.cuts.length ? [['var(--cut)', `cuts: shots retimed separately (${D.cuts.length})`]] : [])]));
  const [, ssdMax] = range(D.ssd.y);
  const ssd = plotFrame({xMax: duration, yMin: 0, yMax: ssdMax, height: 200});
  ssd.svg.id = 'ssd-plot';
  ssd.svg.append(svgEl('path', {class: 'before', id: 'ssd-curve', 'data-points': D.ssd.x.length,
                                d: pathOf(ssd, D.ssd.x, D.ssd.y, false)}));
  const markFrames = (frames, cls, y1, y2, what = 'source frame') => {
    const g = svgEl('g', {class: cls + '-marks'});
    for (const k of frames) {
      const x = ssd.x(k * D.frame_time_in);
      g.append(svgEl('line', {class: cls, x1: x, x2: x, y1, y2, 'data-frame': k},
                     svgEl('title', {}, `${what} ${k}`)));
    }
    ssd.svg.append(g);
  };
  markFrames(D.cuts, 'mark-cut', ssd.top, ssd.bottom, 'cut: a new shot starts at source frame');
  markFrames(D.deleted, 'mark-omitted', ssd.top, ssd.bottom);
  markFrames(D.hidden, 'mark-hidden', (ssd.top + ssd.bottom) / 2, ssd.bottom);
  const ssdCursor = svgEl('line', {class: 'cursor', y1: ssd.top, y2: ssd.bottom});
  ssd.svg.append(ssdCursor);
  cursors.push({plot: ssd, line: ssdCursor});
  ssdSection.append(ssd.svg);

  // The output's frames by kind, one rectangle per run of a kind.
  ssdSection.append(el('h3', {}, 'Output frames'));
  let heldCount = 0, dupCount = 0;
  for (const k of D.kinds) { if (k === 'H') ++heldCount; else if (k === 'D') ++dupCount; }
  ssdSection.append(legend([['#c9c6bd', 'ORIGINAL'], ['var(--dup)', `DUPLICATE (${dupCount})`], ['var(--held)', `HELD (${heldCount})`]]));
  const band = plotFrame({xMax: duration, yMin: 0, yMax: 1, height: 64, yLabels: false});
  band.svg.id = 'kinds-band';
  let start = 0;
  for (let t = 1; t <= framesOut; ++t) {
    if (t < framesOut && D.kinds[t] === D.kinds[start]) continue;
    const x0 = band.x(start * D.frame_time_out), x1 = band.x(t * D.frame_time_out);
    band.svg.append(svgEl('rect', {class: 'kind-' + D.kinds[start], x: x0, y: band.top, width: Math.max(0.5, x1 - x0),
                                   height: band.bottom - band.top, 'data-first': start, 'data-count': t - start},
                          svgEl('title', {}, `${KIND_NAME[D.kinds[start]]}: output frames ${start}–${t - 1}`)));
    start = t;
  }
  const bandCursor = svgEl('line', {class: 'cursor', y1: band.top, y2: band.bottom});
  band.svg.append(bandCursor);
  cursors.push({plot: band, line: bandCursor});
  ssdSection.append(band.svg);

  // ---- the X-sheet --------------------------------------------------------------------------
  // Rows: output frames, or with a film grid the grid frames of the retimed sequence.
  const rowFirst = [];  // per row: its first output frame
  if (grid) {
    for (let t = 0; t < framesOut; ++t) if (rowFirst[D.grid_frames[t]] === undefined) rowFirst[D.grid_frames[t]] = t;
  } else {
    for (let t = 0; t < framesOut; ++t) rowFirst.push(t);
  }
  const rows = rowFirst.length;
  const rowLast = rowFirst.map((_, r) => (r + 1 < rows && rowFirst[r + 1] !== undefined ? rowFirst[r + 1] : framesOut) - 1);
  const drawingNo = new Int32Array(rows), isNew = new Uint8Array(rows);
  let drawings = 0;
  for (let r = 0; r < rows; ++r) {
    const s = D.source_frames[rowFirst[r]];
    isNew[r] = r === 0 || s !== D.source_frames[rowFirst[r - 1]] ? 1 : 0;
    drawings += isNew[r];
    drawingNo[r] = drawings;
  }
  const rowFps = grid ? D.timing_fps : D.fps_out;
  const rowTime = grid ? (r) => r / D.timing_fps : (r) => r * D.frame_time_out;
  const columns = grid
    ? ['grid frame', 'time', 'before: source frame', 'after: drawing', 'source frame', 'kind', 'output frames']
    : ['frame', 'time', 'before: source frame', 'after: drawing', 'source frame', 'kind'];
  const cell = (r, c) => {
    const t = rowFirst[r], kind = D.kinds[t];
    switch (c) {
      case 0: return [String(r)];
      case 1: return [rowTime(r).toFixed(3)];
      case 2: return [String(grid ? (D.grid_source_frames[r] !== undefined ? D.grid_source_frames[r] : '–') : Math.min(r, D.frames_in - 1))];
      case 3: return drawingCell(isNew[r], drawingNo[r]);
      case 4: return [String(D.source_frames[t])];
      case 5: return [KIND_NAME[kind], 'kind-' + kind];
      default: return [rowLast[r] > t ? `${t}–${rowLast[r]}` : String(t)];
    }
  };
  const sheetSection = section('X-sheet');
  sheetSection.append(el('p', {class: 'legend'}, grid
    ? `One row per frame of the ${D.timing_fps} fps film grid; a thick line every second. "after: drawing" numbers each new drawing; | means the drawing is held. ${drawings} drawings.`
    : `One row per output frame; a thick line every second. "after: drawing" numbers each new drawing; | means the drawing is held. ${drawings} drawings.`));
  sheet = makeSheet(rows, columns, cell, (r) => ({second: r > 0 && Math.abs(r / rowFps - Math.round(r / rowFps)) < 1e-9}));
  sheet.element.querySelector('table').dataset.drawings = drawings;
  sheetSection.append(sheet.element);

  exposureSheetSection(D.xdts, rowFps);
  player.show(0);
  reportReady();
})(KOMA);
