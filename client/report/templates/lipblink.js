// koma report, LipBlink: mouth and eye values before and after with the speech intervals
// and the blinks marked, and the sequence of mouth shapes.
(function lipBlinkReport(D) {
  const duration = (D.frames - 1) / D.fps;
  const sec = (frame) => frame / D.unit_fps;  // response frame numbers (grid frames with a grid)
  const trackOf = (id) => D.mouths.find((m) => m.id === id) || D.eyes.find((e) => e.id === id);

  // ---- the face player ------------------------------------------------------------------------
  // A plain face per side: the mouth opens with the first mouth curve, the eyes with the eye
  // curves (one curve: both eyes), each scaled between its track's closed and open levels.
  const mouthTrack = D.mouths[0], eyeTracks = D.eyes.slice(0, 2);
  const curveOf = (id) => D.curves.find((c) => c.id === id);
  const level = (track, v) => {
    const span = track.levels.open - track.levels.closed;
    const x = span !== 0 ? (v - track.levels.closed) / span : 0;
    return Math.max(0, Math.min(1, x));
  };
  const faceSection = section('Face: before and after');
  const makeFace = (side) => {
    const svg = svgEl('svg', {width: 220, height: 220, viewBox: '0 0 220 220', class: 'face', 'data-side': side});
    svg.append(svgEl('circle', {cx: 110, cy: 110, r: 96, class: 'head'}));
    const eyes = [70, 150].map((cx) => {
      const eye = svgEl('ellipse', {cx, cy: 88, rx: 16, ry: 12, class: 'eye ' + side});
      svg.append(eye);
      return eye;
    });
    const mouth = svgEl('ellipse', {cx: 110, cy: 155, rx: 30, ry: 2, class: 'mouth ' + side});
    svg.append(mouth);
    const label = el('div', {class: 'muted'});
    return {svg, eyes, mouth, label};
  };
  const faces = {before: makeFace('before'), after: makeFace('after')};
  faceSection.append(el('div', {class: 'player'},
    el('figure', {id: 'face-before'}, el('figcaption', {}, 'Before (input)'), faces.before.svg, faces.before.label),
    el('figure', {id: 'face-after'}, el('figcaption', {}, 'After (koma)'), faces.after.svg, faces.after.label)));
  const SHAPES = ['closed', 'mid', 'open'];
  const nearestShape = (track, v) => {
    const levels = [track.levels.closed, track.levels.mid, track.levels.open];
    let best = 0;
    for (let i = 1; i < 3; ++i) if (Math.abs(v - levels[i]) < Math.abs(v - levels[best])) best = i;
    return SHAPES[best];
  };
  const drawFace = (face, key, t) => {
    const parts = [];
    if (mouthTrack && curveOf(mouthTrack.id)) {
      const v = curveOf(mouthTrack.id)[key][t];
      face.mouth.setAttribute('ry', (2 + 26 * level(mouthTrack, v)).toFixed(2));
      face.mouth.dataset.value = v;
      parts.push('mouth ' + (key === 'frames_after' ? nearestShape(mouthTrack, v) : v.toFixed(2)));
    }
    face.eyes.forEach((eye, i) => {
      const track = eyeTracks[Math.min(i, eyeTracks.length - 1)];
      if (!track || !curveOf(track.id)) return;
      const v = curveOf(track.id)[key][t];
      eye.setAttribute('ry', (1 + 13 * level(track, v)).toFixed(2));
      eye.dataset.value = v;
    });
    face.label.textContent = parts.join(' · ');
  };
  const cursors = [];  // a time cursor on every plot, following the player
  const facePlayer = makePlayer(D.frames, D.fps, (t) => {
    drawFace(faces.before, 'frames_before', t);
    drawFace(faces.after, 'frames_after', t);
    for (const c of cursors) {
      c.line.setAttribute('x1', c.plot.x(t / D.fps));
      c.line.setAttribute('x2', c.plot.x(t / D.fps));
    }
  }, (t) => `frame ${t} / ${D.frames - 1} · ${seconds(t / D.fps)}` +
            (D.timing_fps > 0 ? ` · grid frame ${Math.floor(t * D.timing_fps / D.fps + 1e-9)}` : ''));
  faceSection.append(facePlayer.controls);
  const addCursor = (plot) => {
    const line = svgEl('line', {class: 'cursor', y1: plot.top, y2: plot.bottom});
    plot.svg.append(line);
    cursors.push({plot, line});
  };

  const curvesSection = section('Mouth and eyes before and after');
  curvesSection.append(legend([['var(--before)', 'before (input)'], ['var(--after)', 'after (koma)'],
                               ['var(--speech)', 'speech'], ['var(--held)', 'blinks']]));
  for (const c of D.curves) {
    const track = trackOf(c.id);
    const isMouth = D.mouths.some((m) => m.id === c.id);
    const [lo1, hi1] = range(c.before.y), [lo2, hi2] = range(c.after.y);
    const plot = plotFrame({xMax: duration, yMin: Math.min(lo1, lo2), yMax: Math.max(hi1, hi2), height: 170});
    plot.svg.classList.add('curve-plot');
    plot.svg.dataset.curve = c.id;
    if (isMouth) {
      const g = svgEl('g', {class: 'speech-marks'});
      for (const [b, e] of track.speech) {
        g.append(svgEl('rect', {class: 'speech', x: plot.x(sec(b)), y: plot.top, width: Math.max(1, plot.x(sec(e)) - plot.x(sec(b))),
                                height: plot.bottom - plot.top, 'data-begin': b, 'data-end': e}));
      }
      plot.svg.append(g);
    } else if (track) {
      const g = svgEl('g', {class: 'blink-marks'});
      for (const b of track.blinks) {
        const x0 = plot.x(sec(b.closing_begin)), x1 = plot.x(sec(b.closed_end + 1 + b.open_span));
        g.append(svgEl('rect', {class: 'blink', x: x0, y: plot.top, width: Math.max(1, x1 - x0), height: plot.bottom - plot.top,
                                'data-closed-begin': b.closed_begin, 'data-hold': b.hold},
                       svgEl('title', {}, `blink: closed from ${b.closed_begin} (${seconds(sec(b.closed_begin))}), hold ${b.hold}` + (b.automatic ? ', automatic' : ''))));
        g.append(svgEl('line', {class: 'blink-line', x1: plot.x(sec(b.closed_begin)), x2: plot.x(sec(b.closed_begin)), y1: plot.top, y2: plot.bottom}));
      }
      plot.svg.append(g);
    }
    plot.svg.append(svgEl('path', {class: 'before', d: pathOf(plot, c.before.x, c.before.y, false)}));
    plot.svg.append(svgEl('path', {class: 'after', d: pathOf(plot, c.after.x, c.after.y, true, duration)}));
    addCursor(plot);
    const what = isMouth ? `${track.speech.length} speech intervals, ${track.holds.length} mouth drawings`
                         : track ? `${track.blinks.length} blinks` : '';
    curvesSection.append(el('h3', {}, `${c.id} — ${what}`), plot.svg);
  }

  // ---- the sequence of mouth shapes -----------------------------------------------------------
  const LETTER = {closed: 'C', mid: 'M', open: 'O'};
  for (const m of D.mouths) {
    const s = section(`Mouth shapes: ${m.id}`);
    s.append(legend([['#7a7a80', 'closed'], ['#d98b5f', 'mid'], ['#c0392b', 'open']]));
    const plot = plotFrame({xMax: duration, yMin: 0, yMax: 1, height: 70, yLabels: false});
    plot.svg.classList.add('shapes');
    plot.svg.dataset.mouth = m.id;
    for (const [begin, length, shape] of m.holds) {
      const x0 = plot.x(sec(begin)), x1 = plot.x(sec(begin + length));
      plot.svg.append(svgEl('rect', {class: 'shape-' + shape, x: x0, y: plot.top, width: Math.max(0.5, x1 - x0 - 0.5),
                                     height: plot.bottom - plot.top, 'data-begin': begin, 'data-length': length, 'data-shape': shape},
                            svgEl('title', {}, `${shape}: frames ${begin}–${begin + length - 1}`)));
      if (x1 - x0 > 9) plot.svg.append(svgEl('text', {class: 'letter', x: (x0 + x1) / 2, y: (plot.top + plot.bottom) / 2 + 4, 'text-anchor': 'middle'}, LETTER[shape] || '?'));
    }
    addCursor(plot);
    s.append(plot.svg);
    s.append(el('p', {class: 'legend'}, m.holds.map(([, , shape]) => LETTER[shape] || '?').join(' ')));
  }
  if (D.timing_fps > 0) {
    section('Film grid', el('p', {}, `Speech, holds and blinks are counted on the ${D.timing_fps} fps film grid: frame numbers above are grid frames (${(1000 / D.timing_fps).toFixed(1)} ms each).`));
  }
  exposureSheetSection(D.xdts, D.timing_fps > 0 ? D.timing_fps : D.fps);
  facePlayer.show(0);
  reportReady();
})(KOMA);
