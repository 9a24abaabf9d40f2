// koma report, LipBlink from a voice (--audio or --rhubarb): the recording's loudness on the
// film grid with the noise floor, the speech thresholds and the speech found; the mouth
// drawings on the same time axis under it; the resulting curves; a face player that plays in
// sync with the recording the page carries (or links to).
(function lipBlinkVoiceReport(D) {
  const V = D.voice;
  const sec = (frame) => frame / D.unit_fps;  // response frame numbers (grid frames with a grid)
  const duration = Math.max((D.frames - 1) / D.fps, V.duration_s);
  const trackOf = (id) => D.mouths.find((m) => m.id === id) || D.eyes.find((e) => e.id === id);
  const curveOf = (id) => D.curves.find((c) => c.id === id);
  const inSpeech = (g) => V.speech.some(([b, e]) => b <= g && g < e);

  // ---- the face player, in sync with the recording ---------------------------------------------
  const mouthTrack = D.mouths[0], eyeTracks = D.eyes.slice(0, 2);
  const level = (track, v) => {
    const span = track.levels.open - track.levels.closed;
    const x = span !== 0 ? (v - track.levels.closed) / span : 0;
    return Math.max(0, Math.min(1, x));
  };
  const SHAPES = ['closed', 'mid', 'open'];
  const nearestShape = (track, v) => {
    const levels = [track.levels.closed, track.levels.mid, track.levels.open];
    let best = 0;
    for (let i = 1; i < 3; ++i) if (Math.abs(v - levels[i]) < Math.abs(v - levels[best])) best = i;
    return SHAPES[best];
  };
  const faceSection = section(V.kind === 'audio' ? 'Voice and face' : 'Face');
  const svg = svgEl('svg', {width: 220, height: 220, viewBox: '0 0 220 220', class: 'face', 'data-side': 'after'});
  svg.append(svgEl('circle', {cx: 110, cy: 110, r: 96, class: 'head'}));
  const eyes = [70, 150].map((cx) => {
    const eye = svgEl('ellipse', {cx, cy: 88, rx: 16, ry: 12, class: 'eye after'});
    svg.append(eye);
    return eye;
  });
  const mouth = svgEl('ellipse', {cx: 110, cy: 155, rx: 30, ry: 2, class: 'mouth after'});
  svg.append(mouth);
  const faceLabel = el('div', {class: 'muted', id: 'face-label'});
  const drawFace = (t) => {
    const parts = [];
    if (mouthTrack && curveOf(mouthTrack.id)) {
      const v = curveOf(mouthTrack.id).frames_after[t];
      mouth.setAttribute('ry', (2 + 26 * level(mouthTrack, v)).toFixed(2));
      mouth.dataset.value = v;
      parts.push('mouth ' + nearestShape(mouthTrack, v));
    }
    eyes.forEach((eye, i) => {
      const track = eyeTracks[Math.min(i, eyeTracks.length - 1)];
      if (!track || !curveOf(track.id)) return;
      const v = curveOf(track.id).frames_after[t];
      eye.setAttribute('ry', (1 + 13 * level(track, v)).toFixed(2));
      eye.dataset.value = v;
    });
    faceLabel.textContent = parts.join(' · ');
  };
  let audio = null;
  const side = el('div', {});
  if (D.audio) {
    audio = el('audio', {id: 'voice-audio', controls: '', preload: 'auto', src: D.audio.src,
                         'data-embedded': D.audio.embedded ? '1' : '0'});
    side.append(el('h3', {}, 'The recording'), audio,
      el('p', {class: 'muted'}, `${D.audio.mime}, ${D.audio.bytes} bytes, ` +
        (D.audio.embedded ? 'in this page.' : `linked: ${decodeURIComponent(D.audio.src)} (keep it beside the page).`)),
      el('p', {class: 'muted'}, `${V.duration_s.toFixed(3)} s, ${V.sample_rate} Hz, ${V.channels} channel${V.channels === 1 ? '' : 's'}. ` +
        'Play plays the recording and the face follows it; the frame buttons, the arrow keys and the scrubber seek both.'));
  } else {
    side.append(el('p', {class: 'muted'}, `Rhubarb cues, ${V.duration_s.toFixed(3)} s (no recording: Play runs on the clock).`));
  }
  faceSection.append(el('div', {class: 'player'},
    el('figure', {id: 'face-after'}, el('figcaption', {}, 'koma'), svg, faceLabel), side));

  const cursors = [];  // a time cursor on every plot, following the player
  const addCursor = (plot) => {
    const line = svgEl('line', {class: 'cursor', y1: plot.top, y2: plot.bottom});
    plot.svg.append(line);
    cursors.push({plot, line});
  };
  const gridFrame = (t) => Math.floor(t * D.unit_fps / D.fps + 1e-9);
  const describe = (t) => `frame ${t} / ${D.frames - 1} · ${seconds(t / D.fps)}` +
    (D.timing_fps > 0 ? ` · grid frame ${gridFrame(t)}` : '') + (inSpeech(gridFrame(t)) ? ' · speech' : ' · pause');

  // Play drives the recording and reads the frame from its clock (the performance clock when
  // there is no recording, it cannot play, or the motion outlasts it); stepping, scrubbing and
  // the keys seek the recording to the frame's time.
  let frame = 0, playing = false, clockMs = 0, clockFrame = 0, onClock = true;
  const counter = el('span', {id: 'counter'});
  const scrub = el('input', {type: 'range', min: 0, max: D.frames - 1, value: 0, step: 1, id: 'scrubber', 'aria-label': 'frame'});
  const play = el('button', {type: 'button', id: 'play'}, 'Play');
  const back = el('button', {type: 'button', id: 'step-back', title: 'previous frame (←)'}, '◀ frame');
  const next = el('button', {type: 'button', id: 'step-forward', title: 'next frame (→)'}, 'frame ▶');
  const show = (t) => {
    frame = Math.max(0, Math.min(D.frames - 1, t));
    scrub.value = frame;
    counter.textContent = describe(frame);
    document.body.dataset.frame = frame;
    drawFace(frame);
    for (const c of cursors) {
      c.line.setAttribute('x1', c.plot.x(frame / D.fps));
      c.line.setAttribute('x2', c.plot.x(frame / D.fps));
    }
  };
  const useClock = () => { onClock = true; clockMs = performance.now(); clockFrame = frame; };
  const tick = (now) => {
    if (!playing) return;
    const t = onClock ? clockFrame + Math.floor((now - clockMs) * D.fps / 1000)
                      : Math.floor(audio.currentTime * D.fps + 1e-6);
    if (t >= D.frames) { show(D.frames - 1); setPlaying(false); return; }
    if (t !== frame) show(t);
    requestAnimationFrame(tick);
  };
  const seekAudio = () => {
    if (audio && audio.readyState >= 1) audio.currentTime = Math.min(frame / D.fps, audio.duration || 0);
  };
  const setPlaying = (on) => {
    playing = on;
    play.textContent = on ? 'Pause' : 'Play';
    document.body.dataset.playing = on ? '1' : '0';
    if (on) {
      if (frame >= D.frames - 1) show(0);
      useClock();
      if (audio && frame / D.fps < (audio.duration || Infinity)) {
        seekAudio();
        onClock = false;
        audio.play().catch(() => { if (playing) useClock(); });  // no sound device: the clock
      }
      requestAnimationFrame(tick);
    } else if (audio && !audio.paused) {
      audio.pause();
    }
  };
  if (audio) {
    // The recording's own controls drive the player too.
    audio.addEventListener('play', () => { if (!playing) { show(Math.floor(audio.currentTime * D.fps + 1e-6)); setPlaying(true); } });
    audio.addEventListener('pause', () => { if (playing && !audio.ended) setPlaying(false); });
    audio.addEventListener('ended', () => { if (playing) useClock(); });  // the motion may outlast it
    audio.addEventListener('seeked', () => {
      if (!playing && Math.abs(audio.currentTime - frame / D.fps) >= 0.5 / D.fps) show(Math.floor(audio.currentTime * D.fps + 1e-6));
    });
    audio.addEventListener('loadedmetadata', () => { document.body.dataset.audio = 'loaded'; });
    audio.addEventListener('error', () => { document.body.dataset.audio = 'error'; });
  }
  const seek = (t) => { setPlaying(false); show(t); seekAudio(); };
  play.addEventListener('click', () => setPlaying(!playing));
  back.addEventListener('click', () => seek(frame - 1));
  next.addEventListener('click', () => seek(frame + 1));
  scrub.addEventListener('input', () => seek(+scrub.value));
  document.addEventListener('keydown', (e) => {
    if (e.target instanceof HTMLInputElement || e.target instanceof HTMLButtonElement ||
        e.target instanceof HTMLAudioElement) return;
    if (e.key === 'ArrowRight') next.click();
    else if (e.key === 'ArrowLeft') back.click();
    else if (e.key === ' ') { e.preventDefault(); play.click(); }
  });
  faceSection.append(el('div', {class: 'controls'}, play, back, next, scrub, counter));

  // ---- loudness on the film grid, and the mouth drawings under it ------------------------------
  const grid = D.timing_fps > 0 ? `the ${D.timing_fps} fps film grid` : `the motion's ${D.fps} fps frames`;
  const voiceSection = section(V.kind === 'audio' ? 'Loudness, speech and mouth drawings' : 'Speech and mouth drawings');
  if (V.kind === 'audio') {
    voiceSection.append(el('p', {class: 'muted'}, `Loudness: RMS of each frame of ${grid} (${(1000 / V.frame_fps).toFixed(1)} ms), dBFS. ` +
      `Noise floor ${V.noise_floor_dbfs.toFixed(1)} dBFS; speech starts above ${V.start_dbfs.toFixed(1)} dBFS and lasts while above ${V.stay_dbfs.toFixed(1)} dBFS; ` +
      `the speech's loud level ${V.loud_dbfs.toFixed(1)} dBFS.`));
    voiceSection.append(legend([['var(--loudness)', 'loudness'], ['var(--speech)', 'speech'], ['var(--floor)', 'noise floor'],
                                ['var(--threshold)', 'start (solid) and stay (dashed) thresholds'], ['var(--key)', 'loud level']]));
    const [lo0, hi0] = range(V.loudness.y);
    const yMin = Math.max(lo0, Math.min(V.noise_floor_dbfs - 12, -60), -120);
    const yMax = Math.max(hi0, V.loud_dbfs, V.start_dbfs) + 3;
    const plot = plotFrame({xMax: duration, yMin, yMax, height: 200});
    plot.svg.classList.add('loudness-plot');
    const marks = svgEl('g', {class: 'speech-marks'});
    for (const [b, e] of V.speech) {
      marks.append(svgEl('rect', {class: 'speech', x: plot.x(sec(b)), y: plot.top, width: Math.max(1, plot.x(sec(e)) - plot.x(sec(b))),
                                  height: plot.bottom - plot.top, 'data-begin': b, 'data-end': e},
                         svgEl('title', {}, `speech: frames ${b}–${e - 1} (${seconds(sec(b))} – ${seconds(sec(e))})`)));
    }
    plot.svg.append(marks);
    // Labels at the right end, each in its own column: equal levels (start = stay when both sit
    // at min_speech_dbfs) stay readable.
    const levelLine = (cls, dbfs, text, column) => {
      const y = plot.y(Math.max(yMin, dbfs)).toFixed(1);
      plot.svg.append(svgEl('line', {class: 'level ' + cls, x1: plot.left, x2: plot.right, y1: y, y2: y, 'data-dbfs': dbfs}));
      plot.svg.append(svgEl('text', {class: 'level-label', x: plot.right - 4 - 110 * column, y: +y - 3, 'text-anchor': 'end'}, `${text} ${dbfs.toFixed(1)}`));
    };
    const clamped = V.loudness.y.map((v) => Math.max(yMin, v));
    plot.svg.append(svgEl('path', {class: 'loudness', d: pathOf(plot, V.loudness.x, clamped, true, V.frames / V.frame_fps),
                                   'data-points': V.loudness.x.length}));
    levelLine('noise-floor', V.noise_floor_dbfs, 'noise floor', 0);
    levelLine('threshold-stay', V.stay_dbfs, 'stay', 1);
    levelLine('threshold-start', V.start_dbfs, 'start', 0);
    levelLine('loud-level', V.loud_dbfs, 'loud', 0);
    addCursor(plot);
    voiceSection.append(plot.svg);
  }
  const LETTER = {closed: 'C', mid: 'M', open: 'O'};
  for (const m of D.mouths) {
    voiceSection.append(el('h3', {}, `Mouth drawings: ${m.id} (${m.holds.length})`));
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
    voiceSection.append(plot.svg);
  }
  voiceSection.append(legend([['#7a7a80', 'closed'], ['#d98b5f', 'mid'], ['#c0392b', 'open']]));

  // ---- the curves written -----------------------------------------------------------------------
  const curvesSection = section('Mouth and eyes written');
  curvesSection.append(legend([['var(--after)', 'after (koma)'], ['var(--speech)', 'speech'], ['var(--held)', 'blinks']]));
  for (const c of D.curves) {
    const track = trackOf(c.id);
    const isMouth = D.mouths.some((m) => m.id === c.id);
    const [lo, hi] = range(c.after.y);
    const plot = plotFrame({xMax: duration, yMin: Math.min(lo, track ? track.levels.closed : lo), yMax: Math.max(hi, track ? track.levels.open : hi), height: 150});
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
    plot.svg.append(svgEl('path', {class: 'after', d: pathOf(plot, c.after.x, c.after.y, true, (D.frames - 1) / D.fps)}));
    addCursor(plot);
    const what = isMouth ? `${track.speech.length} speech intervals, ${track.holds.length} mouth drawings`
                         : track ? `${track.blinks.length} blinks` : '';
    curvesSection.append(el('h3', {}, `${c.id} — ${what}`), plot.svg);
  }
  if (D.timing_fps > 0) {
    section('Film grid', el('p', {}, `Loudness, speech, holds and blinks are counted on the ${D.timing_fps} fps film grid: frame numbers above are grid frames (${(1000 / D.timing_fps).toFixed(1)} ms each); the motion written has ${D.frames} frames at ${D.fps} fps.`));
  }
  exposureSheetSection(D.xdts, D.timing_fps > 0 ? D.timing_fps : D.fps);
  show(0);
  reportReady();
})(KOMA);
