// koma report, LipBlink: mouth and eye values before and after with the speech intervals
// and the blinks marked, and the sequence of mouth shapes.
(function lipBlinkReport(D) {
  const duration = (D.frames - 1) / D.fps;
  const sec = (frame) => frame / D.unit_fps;  // response frame numbers (grid frames with a grid)
  const trackOf = (id) => D.mouths.find((m) => m.id === id) || D.eyes.find((e) => e.id === id);

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
    const what = isMouth ? `${track.speech.length} speech intervals, ${track.holds.length} mouth drawings`
                         : track ? `${track.blinks.length} blinks` : '';
    curvesSection.append(el('h3', {}, `${c.id} — ${what}`), plot.svg);
  }

  // ---- the sequence of mouth shapes -----------------------------------------------------------
  const LETTER = {closed: 'C', mid: 'M', open: 'O'};
  for (const m of D.mouths) {
    const s = section(`Mouth shapes: ${m.id}`);
    s.append(legend([['#7a7a80', 'closed'], ['#d98b5f', 'mid'], ['#c0392b', 'open']]));
    const plot = plotFrame({xMax: duration, yMin: 0, yMax: 1, height: 70});
    plot.svg.classList.add('shapes');
    plot.svg.dataset.mouth = m.id;
    for (const [begin, length, shape] of m.holds) {
      const x0 = plot.x(sec(begin)), x1 = plot.x(sec(begin + length));
      plot.svg.append(svgEl('rect', {class: 'shape-' + shape, x: x0, y: plot.top, width: Math.max(0.5, x1 - x0 - 0.5),
                                     height: plot.bottom - plot.top, 'data-begin': begin, 'data-length': length, 'data-shape': shape},
                            svgEl('title', {}, `${shape}: frames ${begin}–${begin + length - 1}`)));
      if (x1 - x0 > 9) plot.svg.append(svgEl('text', {x: (x0 + x1) / 2, y: (plot.top + plot.bottom) / 2 + 4, 'text-anchor': 'middle'}, LETTER[shape] || '?'));
    }
    s.append(plot.svg);
    s.append(el('p', {class: 'legend'}, m.holds.map(([, , shape]) => LETTER[shape] || '?').join(' ')));
  }
  if (D.timing_fps > 0) {
    section('Film grid', el('p', {}, `Speech, holds and blinks are counted on the ${D.timing_fps} fps film grid: frame numbers above are grid frames (${(1000 / D.timing_fps).toFixed(1)} ms each).`));
  }
  reportReady();
})(KOMA);
