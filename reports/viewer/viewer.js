// aoeval's image viewer (CONTRACT §11): zoom to single pixels, pan, a value probe, A/B flip,
// exposure/contrast and false colour over the float data of the EXRs a page shows. Our own code,
// no library, no network: it works from file://.
//
// Why script files: Chromium forbids fetch() and canvas pixel reads of file:// images, but a
// <script src> loads from file://. So reports/viewer.cpp writes each EXR's channels as a script
// (viewer-data/NAME.js) that stores, in window.AOEVAL_DATA[NAME], {w, h, frames, channels: {CH:
// [base64 of little-endian float32 per frame]}, mask: [base64 of one byte per pixel per frame]}
// and, for a sequence's kept frames, frame_numbers (the sequence frame of each) and fps;
// a viewer loads its scripts only when it is opened, so the page paints as fast as without it.
// The default data is compact (reports/viewer.h, ViewerData; issue 42): encoding
// "shuffled-deflate", every plane and mask zlib-deflated, each plane's bytes shuffled (all first
// bytes, then all second bytes, ...) and, as kinds: {CH: ["h", "q" or "f" per frame]} says,
// float16 or int16 fixed point in steps of 1/4096 (values within 1e-3 of the EXR's) or float32
// (exact); a number in place of a frame's plane or mask: it repeats that earlier frame. The
// deflated planes and masks lie in one string, rec.bin, each named by [offset, length]: the
// script is loaded with charset x-user-defined, so each of its bytes is one character whose
// code & 255 is the byte (about 1.02 bytes of file per byte of data; base64 took 1.33). load()
// inflates them all with the browser's DecompressionStream when the viewer opens;
// `--viewer-exact` writes the plain form.
//
// Markup (reports/viewer.cpp writes it): <div class="aoeval-viewer" data-kind="compare|gbuffer|maps"
// data-a="viewer-data/REF.js" data-b="viewer-data/EST.js" data-labels="reference,estimate">
// holding the static images (what a reader without JavaScript sees). Opening it (a click on the
// images or the "open viewer" button) adds the panels; then element.aoevalProbe(x, y[, frame])
// returns {reference, estimate, error, stderr} (compare) or every channel's value (gbuffer; maps:
// a sequence's flicker and lag maps, each channel a panel through inferno, 0..its own scale).
'use strict';
(function () {
  const DATA = (window.AOEVAL_DATA = window.AOEVAL_DATA || {});
  const pending = {};
  // Loads one data script once; resolves with its record, compact planes already decoded.
  function load(src) {
    const name = src.replace(/^.*\//, '').replace(/\.js$/, '');
    if (!pending[name])
      pending[name] = (DATA[name] ? Promise.resolve(DATA[name]) : new Promise(function (resolve, reject) {
        const s = document.createElement('script');
        s.charset = 'x-user-defined';  // compact data: one byte, one character (see the top)
        s.src = src;
        s.onload = function () {
          if (DATA[name]) resolve(DATA[name]);
          else reject(new Error(src + ' holds no viewer data'));
        };
        s.onerror = function () { reject(new Error(src + ' did not load')); };
        document.head.appendChild(s);
      })).then(decodeRecord);
    return pending[name];
  }

  // Compact data (see the top): inflate, unshuffle and widen every plane to a Float32Array and
  // every mask to a Uint8Array, in place, once.
  async function inflate(u) {
    const stream = new Blob([u]).stream().pipeThrough(new DecompressionStream('deflate'));
    return new Uint8Array(await new Response(stream).arrayBuffer());
  }
  let HALF = null;  // float16 bits -> value, all 65536 of them
  function halfTable() {
    if (HALF) return HALF;
    HALF = new Float32Array(65536);
    for (let h = 0; h < 65536; ++h) {
      const s = h & 0x8000 ? -1 : 1, e = (h >> 10) & 31, m = h & 1023;
      HALF[h] = e === 0 ? s * m * Math.pow(2, -24) : e === 31 ? (m ? NaN : s * Infinity)
        : s * (1024 + m) * Math.pow(2, e - 25);
    }
    return HALF;
  }
  function unpack(u, kind) {
    const size = kind === 'f' ? 4 : 2, n = u.length / size, out = new Float32Array(n);
    if (kind === 'h') {
      const t = halfTable();
      for (let i = 0; i < n; ++i) out[i] = t[u[i] | (u[n + i] << 8)];
    } else if (kind === 'q') {  // int16 fixed point, steps of 1/FIXED
      for (let i = 0; i < n; ++i) out[i] = (((u[i] | (u[n + i] << 8)) << 16) >> 16) / FIXED;
    } else {
      const v = new DataView(new ArrayBuffer(4));
      for (let i = 0; i < n; ++i) {
        for (let b = 0; b < 4; ++b) v.setUint8(b, u[b * n + i]);
        out[i] = v.getFloat32(0, true);
      }
    }
    return out;
  }
  const FIXED = 4096;  // kViewerFixedScale
  async function decodeRecord(rec) {
    if (rec.encoding !== 'shuffled-deflate' || rec._decoded) return rec;
    const jobs = [];
    // A number in a frame's place: that frame repeats the earlier frame it names (decoded once).
    const bin = rec.bin || '';
    const decode = function (list, f, as) {
      if (!Array.isArray(list[f])) return;
      const off = list[f][0], u = new Uint8Array(list[f][1]);
      for (let i = 0; i < u.length; ++i) u[i] = bin.charCodeAt(off + i) & 255;
      jobs.push(inflate(u).then(function (v) { list[f] = as(v); }));
    };
    for (const ch of Object.keys(rec.channels))
      rec.channels[ch].forEach(function (_, f) { decode(rec.channels[ch], f, (u) => unpack(u, rec.kinds[ch][f])); });
    rec.mask.forEach(function (_, f) { decode(rec.mask, f, (u) => u); });
    await Promise.all(jobs);
    delete rec.bin;
    for (const list of Object.values(rec.channels).concat([rec.mask]))
      list.forEach(function (v, f) { if (typeof v === 'number') list[f] = list[v]; });
    rec._decoded = true;
    return rec;
  }

  // base64 -> bytes; floats are read little-endian whatever the machine (DataView).
  function bytes(b64) {
    const bin = atob(b64), u = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; ++i) u[i] = bin.charCodeAt(i);
    return u;
  }
  function floats(b64) {
    const u = bytes(b64), v = new DataView(u.buffer), f = new Float32Array(u.length / 4);
    for (let i = 0; i < f.length; ++i) f[i] = v.getFloat32(4 * i, true);
    return f;
  }
  // A channel of one frame, decoded on first use. Returns null when the file lacks it.
  function plane(rec, ch, frame) {
    const key = '_' + ch + '@' + frame;
    if (!(key in rec)) {
      const list = ch === 'mask' ? rec.mask : rec.channels[ch];
      const v = list ? list[Math.min(frame, list.length - 1)] : null;
      rec[key] = v === null ? null : typeof v !== 'string' ? v : (ch === 'mask' ? bytes : floats)(v);
    }
    return rec[key];
  }

  // Colour maps as 256 stops, linearly interpolated: inferno and RdBu reversed (blue = estimate
  // lower), the mosaics' own (colour_maps.js, generated from drawing/error_maps.cpp).
  const INFERNO = AOEVAL_COLOUR_MAPS.inferno, RDBU = AOEVAL_COLOUR_MAPS.rdbu;
  function lut(stops, t) {
    const x = Math.min(1, Math.max(0, t)) * (stops.length - 1), i = Math.min(stops.length - 2, x | 0);
    const f = x - i, a = stops[i], b = stops[i + 1];
    return [a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2])];
  }
  // Linear [0, 1] -> sRGB byte (displayed luminance = value, like the mosaics' grey panels).
  function srgb(v) {
    v = Math.min(1, Math.max(0, v));
    return 255 * (v <= 0.0031308 ? 12.92 * v : 1.055 * Math.pow(v, 1 / 2.4) - 0.055);
  }
  const GREY = 64, GREEN = [0, 255, 0];  // uncompared pixels; NaN or infinite values

  // The automatic scale of drawing/error_maps.h: nice_ceiling(99th percentile of |v|), its rule
  // generated with the maps.
  const autoScale = AOEVAL_COLOUR_MAPS.autoScale;
  function fmt(v) {
    if (v === null || v === undefined) return '–';
    return Array.isArray(v) ? v.map(fmt).join(', ') : Number(v).toPrecision(6);
  }
  function tag(name, cls, parent, text) {
    const e = document.createElement(name);
    if (cls) e.className = cls;
    if (text !== undefined) e.textContent = text;
    if (parent) parent.appendChild(e);
    return e;
  }

  // The panels of a viewer and the values each shows, per frame. kind: 'ao' (grey or false
  // colour, exposure and contrast), 'abs' and 'stderr' (inferno, 0..scale), 'signed' (RdBu,
  // -scale..scale), 'rgb' (normals, n * 0.5 + 0.5) and 'depth' (inferno, near = bright).
  function panelsOf(kind, recs, labels) {
    if (kind === 'gbuffer') {
      const g = recs[0];
      return [{ label: 'normals N', kind: 'rgb', values: (f) => ['N.X', 'N.Y', 'N.Z'].map((c) => plane(g, c, f)) },
        { label: 'depth Z', kind: 'depth', values: (f) => plane(g, 'Z', f) }];
    }
    if (kind === 'maps') {
      const g = recs[0];
      return Object.keys(g.channels).map((c) => ({ label: c, kind: 'stderr', values: (f) => plane(g, c, f) }));
    }
    const a = recs[0], b = recs[1], errs = {};
    const err = function (f) {  // e - r in float32, as the EXRs' floats subtract
      if (!errs[f]) {
        const r = plane(a, 'AO', f), e = plane(b, 'AO', f), d = new Float32Array(r.length);
        for (let i = 0; i < d.length; ++i) d[i] = e[i] - r[i];
        errs[f] = d;
      }
      return errs[f];
    };
    const p = [{ label: labels[0], kind: 'ao', values: (f) => plane(a, 'AO', f) },
      { label: labels[1], kind: 'ao', flips: true, values: (f) => plane(b, 'AO', f), other: (f) => plane(a, 'AO', f) },
      { label: '|' + labels[1] + ' − ' + labels[0] + '|', kind: 'abs', values: err },
      { label: labels[1] + ' − ' + labels[0], kind: 'signed', values: err }];
    if (a.channels.AO_stderr) p.push({ label: labels[0] + ' AO_stderr', kind: 'stderr', values: (f) => plane(a, 'AO_stderr', f) });
    return p;
  }

  // One opened viewer: state shared by its panels (so they move together), the panels' canvases.
  function Viewer(el, recs) {
    const kind = el.dataset.kind || 'compare';
    const labels = (el.dataset.labels || 'reference,estimate').split(',');
    const w = recs[0].w, h = recs[0].h, frames = recs[0].frames || 1;
    // Sequence frame numbers of the data's frames (a long sequence keeps some of its frames):
    // the slider, the readout and aoevalProbe's frame argument speak in them.
    const numbers = recs[0].frame_numbers || Array.from({ length: frames }, (_, i) => i);
    for (const r of recs) if (r.w !== w || r.h !== h) throw new Error('viewer: images differ in size');
    const st = { scale: 1, tx: 0, ty: 0, grid: true, flip: false, hoverFlip: false, exposure: 0,
      contrast: 1, falseColour: false, frame: 0, probe: null };
    const masks = {};
    const mask = function (f) {  // compared pixels: covered in every image (A > 0.5)
      if (!masks[f]) {
        const m = new Uint8Array(w * h).fill(1);
        for (const r of recs) { const p = plane(r, 'mask', f); if (p) for (let i = 0; i < m.length; ++i) m[i] &= p[i]; }
        masks[f] = m;
      }
      return masks[f];
    };
    const panels = panelsOf(kind, recs, labels);
    const root = tag('div', 'av-root'), bar = tag('div', 'av-bar', root);
    const grid = tag('div', 'av-panels', root), readout = tag('div', 'av-readout', root, 'move over an image: pixel (x, y) and its values');
    const help = tag('div', 'av-help', root);
    help.hidden = true;
    help.innerHTML = '<b>Keys</b> (pointer over the viewer): wheel or + / − zoom, drag or arrows pan, ' +
      '0 fit, 1 one image pixel per screen pixel, g pixel grid, f or hovering “A/B” flips the ' +
      'estimate with the reference, e / E exposure up / down, c / C contrast, r reset exposure and ' +
      'contrast, m false colour, , / . previous / next frame, p play, ? this help, Esc close.';
    const cssW = Math.max(1, Math.round(w * Math.min(1, 400 / w))), cssH = Math.max(1, Math.round(h * cssW / w));
    const fit = function () { st.scale = cssW / w; st.tx = 0; st.ty = 0; };
    fit();
    const dpr = window.devicePixelRatio || 1;
    for (const p of panels) {
      const box = tag('figure', 'av-panel', grid);
      box.style.width = cssW + 'px';
      p.title = tag('figcaption', 'av-label', box, p.label);
      p.canvas = tag('canvas', 'av-canvas', box);
      p.canvas.width = Math.round(cssW * dpr); p.canvas.height = Math.round(cssH * dpr);
      p.canvas.style.width = cssW + 'px'; p.canvas.style.height = cssH + 'px';
      p.off = document.createElement('canvas');
      p.off.width = w; p.off.height = h;
      p.bar = tag('canvas', 'av-colourbar', box);
      p.bar.width = 256; p.bar.height = 1;
      p.ticks = tag('div', 'av-ticks', box);
    }

    // Scales of the false-colour panels, fixed from frame 0 so that frames compare.
    for (const p of panels)
      if (p.kind === 'abs' || p.kind === 'signed' || p.kind === 'stderr') p.range = autoScale(p.values(0), mask(0));
    const gain = function () { return Math.pow(2, st.exposure); };
    // Value -> [0, 1] position on the panel's colour bar, and the bar's end and middle labels.
    function position(p, v) {
      if (p.kind === 'ao') return ((v * gain()) - 0.5) * st.contrast + 0.5;
      if (p.kind === 'signed') return 0.5 + 0.5 * v * gain() / p.range;
      if (p.kind === 'depth') return 1 - (v - p.zlo) / Math.max(1e-30, p.zhi - p.zlo);
      return Math.abs(v) * gain() / p.range;
    }
    function ticks(p) {
      const g = gain();
      if (p.kind === 'ao') return [0, 0.5, 1].map((t) => ((t - 0.5) / st.contrast + 0.5) / g);
      if (p.kind === 'signed') return [-p.range / g, 0, p.range / g];
      if (p.kind === 'depth') return [p.zhi, (p.zlo + p.zhi) / 2, p.zlo];
      return [0, p.range / g / 2, p.range / g];
    }
    function colour(p, t) {
      if (p.kind === 'signed') return lut(RDBU, t);
      if (p.kind === 'ao' && !st.falseColour) { const g = srgb(t); return [g, g, g]; }
      return lut(INFERNO, t);
    }
    // Recomputes a panel's image (exposure, contrast, map, frame or flip changed).
    function paint(p) {
      const f = st.frame, m = mask(f), ctx = p.off.getContext('2d'), img = ctx.createImageData(w, h), d = img.data;
      const flipped = p.flips && (st.flip || st.hoverFlip);
      const v = flipped ? p.other(f) : p.values(f);
      p.title.textContent = flipped ? labels[0] + ' (flipped; f or hover A/B)' : p.label;
      p.title.classList.toggle('av-flipped', !!flipped);
      if (p.kind === 'depth') {
        p.zlo = Infinity; p.zhi = -Infinity;
        for (let i = 0; i < v.length; ++i) if (m[i] && isFinite(v[i])) { p.zlo = Math.min(p.zlo, v[i]); p.zhi = Math.max(p.zhi, v[i]); }
      }
      for (let i = 0, o = 0; i < w * h; ++i, o += 4) {
        let c;
        if (!m[i]) c = [GREY, GREY, GREY];
        else if (p.kind === 'rgb') c = v.map((ch) => (isFinite(ch[i]) ? 255 * Math.min(1, Math.max(0, ch[i] * 0.5 + 0.5)) : NaN));
        else c = isFinite(v[i]) ? colour(p, position(p, v[i])) : GREEN;
        if (c.some(isNaN)) c = GREEN;
        d[o] = c[0]; d[o + 1] = c[1]; d[o + 2] = c[2]; d[o + 3] = 255;
      }
      ctx.putImageData(img, 0, 0);
      const bctx = p.bar.getContext('2d'), b = bctx.createImageData(256, 1);
      for (let x = 0; x < 256; ++x) {
        const c = p.kind === 'rgb' ? [x, x, x] : colour(p, x / 255);
        b.data.set([c[0], c[1], c[2], 255], 4 * x);
      }
      bctx.putImageData(b, 0, 0);
      p.ticks.textContent = '';
      for (const t of p.kind === 'rgb' ? ['−1', 'N', '1'] : ticks(p)) tag('span', '', p.ticks, typeof t === 'number' ? String(Number(t.toPrecision(3))) : t);
    }
    // Draws every panel with the shared zoom and pan; a pixel grid from 6 screen pixels per image
    // pixel up; the probed pixel outlined in all panels.
    let queued = false;
    function draw() {
      queued = false;
      for (const p of panels) {
        const ctx = p.canvas.getContext('2d');
        ctx.setTransform(1, 0, 0, 1, 0, 0);
        ctx.fillStyle = '#333';
        ctx.fillRect(0, 0, p.canvas.width, p.canvas.height);
        ctx.imageSmoothingEnabled = false;  // nearest neighbour: a pixel is a square
        const s = st.scale * dpr;
        ctx.setTransform(s, 0, 0, s, st.tx * dpr, st.ty * dpr);
        ctx.drawImage(p.off, 0, 0);
        ctx.setTransform(1, 0, 0, 1, 0, 0);
        if (st.grid && st.scale >= 6) {
          const x0 = Math.max(0, Math.floor(-st.tx / st.scale)), x1 = Math.min(w, Math.ceil((cssW - st.tx) / st.scale));
          const y0 = Math.max(0, Math.floor(-st.ty / st.scale)), y1 = Math.min(h, Math.ceil((cssH - st.ty) / st.scale));
          ctx.strokeStyle = 'rgba(128,128,128,0.6)'; ctx.lineWidth = 1;
          ctx.beginPath();
          for (let x = x0; x <= x1; ++x) { const X = Math.round((st.tx + x * st.scale) * dpr) + 0.5; ctx.moveTo(X, 0); ctx.lineTo(X, p.canvas.height); }
          for (let y = y0; y <= y1; ++y) { const Y = Math.round((st.ty + y * st.scale) * dpr) + 0.5; ctx.moveTo(0, Y); ctx.lineTo(p.canvas.width, Y); }
          ctx.stroke();
        }
        if (st.probe) {
          ctx.strokeStyle = '#0ff'; ctx.lineWidth = 2;
          ctx.strokeRect((st.tx + st.probe[0] * st.scale) * dpr, (st.ty + st.probe[1] * st.scale) * dpr,
            Math.max(2, st.scale * dpr), Math.max(2, st.scale * dpr));
        }
      }
    }
    const redraw = function () { if (!queued) { queued = true; requestAnimationFrame(draw); } };
    const repaint = function () { panels.forEach(paint); redraw(); };

    // The values under the cursor (CONTRACT §11): the EXRs' floats, unrounded with exact data
    // (`--viewer-exact`); with the default compact data within 1e-3 of them (float16 planes).
    function probe(x, y, frame) {
      const f = frame === undefined ? st.frame : numbers.indexOf(frame);
      if (!(Number.isInteger(x) && Number.isInteger(y) && x >= 0 && y >= 0 && x < w && y < h))
        throw new RangeError('aoevalProbe: pixel (' + x + ', ' + y + ') is outside ' + w + 'x' + h);
      if (!(Number.isInteger(f) && f >= 0 && f < frames)) throw new RangeError('aoevalProbe: no frame ' + frame + ' (frames ' + numbers.join(', ') + ')');
      const i = y * w + x;
      if (kind === 'gbuffer' || kind === 'maps') {
        const out = {};
        for (const c of Object.keys(recs[0].channels)) out[c] = plane(recs[0], c, f)[i];
        return out;
      }
      const r = plane(recs[0], 'AO', f)[i], e = plane(recs[1], 'AO', f)[i], sd = plane(recs[0], 'AO_stderr', f);
      return { reference: r, estimate: e, error: Math.fround(e - r), stderr: sd ? sd[i] : null };
    }
    function showProbe() {
      if (!st.probe) return;
      const [x, y] = st.probe, v = probe(x, y);
      const parts = Object.keys(v).map((k) => k + ' ' + fmt(v[k]));
      readout.textContent = 'pixel (' + x + ', ' + y + ')' + (frames > 1 ? ' frame ' + numbers[st.frame] : '') + ': ' +
        parts.join(' · ') + (mask(st.frame)[y * w + x] ? '' : ' (not compared: uncovered)');
    }

    // Zoom by `factor` keeping the image point under (cx, cy) (CSS pixels in a canvas) still.
    function zoom(factor, cx, cy) {
      if (cx === undefined) { cx = cssW / 2; cy = cssH / 2; }
      const s = Math.min(256, Math.max(cssW / w / 4, st.scale * factor));
      st.tx = cx - (cx - st.tx) * s / st.scale; st.ty = cy - (cy - st.ty) * s / st.scale; st.scale = s;
      redraw();
    }
    function pan(dx, dy) { st.tx += dx; st.ty += dy; redraw(); }
    let drag = null;
    for (const p of panels) {
      const c = p.canvas;
      c.addEventListener('wheel', function (ev) {
        ev.preventDefault();
        zoom(ev.deltaY < 0 ? 1.25 : 0.8, ev.offsetX, ev.offsetY);
      }, { passive: false });
      c.addEventListener('pointerdown', function (ev) { drag = [ev.clientX, ev.clientY]; c.setPointerCapture(ev.pointerId); });
      c.addEventListener('pointerup', function () { drag = null; });
      c.addEventListener('pointermove', function (ev) {
        if (drag) { pan(ev.clientX - drag[0], ev.clientY - drag[1]); drag = [ev.clientX, ev.clientY]; }
        const x = Math.floor((ev.offsetX - st.tx) / st.scale), y = Math.floor((ev.offsetY - st.ty) / st.scale);
        st.probe = x >= 0 && y >= 0 && x < w && y < h ? [x, y] : null;
        showProbe();
        redraw();
      });
    }

    // The toolbar: each control also has a key (help).
    function button(text, title, action) {
      const b = tag('button', 'av-button', bar, text);
      b.type = 'button'; b.title = title;
      b.addEventListener('click', action);
      return b;
    }
    button('fit', 'fit the image (0)', function () { fit(); redraw(); });
    button('1:1', 'one image pixel per screen pixel (1)', function () { zoom(1 / st.scale); });
    button('+', 'zoom in (+, wheel)', function () { zoom(2); });
    button('−', 'zoom out (−, wheel)', function () { zoom(0.5); });
    const gridButton = button('grid', 'pixel grid when zoomed in (g)', function () { st.grid = !st.grid; gridButton.classList.toggle('av-on', st.grid); redraw(); });
    gridButton.classList.add('av-on');
    let flipButton = null;
    if (kind === 'compare') {
      flipButton = button('A/B', 'flip the estimate with the reference: hover, or click / f to hold', function () { st.flip = !st.flip; flipButton.classList.toggle('av-on', st.flip); repaint(); });
      flipButton.addEventListener('mouseenter', function () { st.hoverFlip = true; repaint(); });
      flipButton.addEventListener('mouseleave', function () { st.hoverFlip = false; repaint(); });
    }
    const falseButton = button('false colour', 'AO panels in false colour (inferno) with its colour bar (m)', function () { st.falseColour = !st.falseColour; falseButton.classList.toggle('av-on', st.falseColour); repaint(); });
    function slider(label, min, max, step, value, set, show) {
      show = show || String;
      const l = tag('label', 'av-slider', bar, label + ' ');
      const s = tag('input', '', l);
      s.type = 'range'; s.min = min; s.max = max; s.step = step; s.value = value;
      const out = tag('output', '', l, show(value));
      s.addEventListener('input', function () { set(Number(s.value)); out.textContent = show(Number(s.value)); repaint(); });
      return { sync: function (v) { s.value = v; out.textContent = show(v); } };
    }
    const exposure = slider('exposure', -8, 8, 0.25, 0, function (v) { st.exposure = v; });
    const contrast = slider('contrast', 0.25, 4, 0.05, 1, function (v) { st.contrast = v; });
    let frameSlider = null, timer = null;
    function setFrame(f) { st.frame = (f + frames) % frames; if (frameSlider) frameSlider.sync(st.frame); repaint(); showProbe(); }
    function play() {
      if (timer) { clearInterval(timer); timer = null; return; }
      timer = setInterval(function () { setFrame(st.frame + 1); }, 1000 / (recs[0].fps || 10));
    }
    if (frames > 1) {  // sequences (CONTRACT §10): a frame slider and play
      frameSlider = slider('frame', 0, frames - 1, 1, 0, function (v) { st.frame = v; showProbe(); }, (i) => String(numbers[i]));
      button('play', 'play the frames (p)', play);
    }
    button('?', 'keyboard help (?)', function () { help.hidden = !help.hidden; });
    button('close', 'back to the static images (Esc)', function () { close(); });

    el.tabIndex = 0;
    el.addEventListener('mouseenter', function () { el.focus({ preventScroll: true }); });
    el.addEventListener('keydown', function (ev) {
      const k = ev.key, step = 0.1 * cssW;
      const keys = {
        '+': () => zoom(2), '=': () => zoom(2), '-': () => zoom(0.5), '0': () => { fit(); redraw(); }, '1': () => zoom(1 / st.scale),
        ArrowLeft: () => pan(step, 0), ArrowRight: () => pan(-step, 0), ArrowUp: () => pan(0, step), ArrowDown: () => pan(0, -step),
        g: () => gridButton.click(), f: () => flipButton && flipButton.click(), m: () => falseButton.click(),
        e: () => { st.exposure += 0.5; exposure.sync(st.exposure); repaint(); }, E: () => { st.exposure -= 0.5; exposure.sync(st.exposure); repaint(); },
        c: () => { st.contrast *= 1.25; contrast.sync(st.contrast); repaint(); }, C: () => { st.contrast /= 1.25; contrast.sync(st.contrast); repaint(); },
        r: () => { st.exposure = 0; st.contrast = 1; exposure.sync(0); contrast.sync(1); repaint(); },
        ',': () => setFrame(st.frame - 1), '.': () => setFrame(st.frame + 1), p: () => frames > 1 && play(),
        '?': () => { help.hidden = !help.hidden; }, Escape: () => close(),
      };
      if (keys[k] && !ev.ctrlKey && !ev.metaKey && !ev.altKey) { ev.preventDefault(); keys[k](); }
    });
    function close() { if (timer) play(); el.classList.remove('av-open'); root.remove(); el.aoevalViewer = null; }

    el.classList.add('av-open');
    el.appendChild(root);
    repaint();
    el.aoevalProbe = probe;
    // For tests and scripts: the view's state (zoom in screen pixels per image pixel, pan, flip...).
    el.aoevalView = function () { return Object.assign(JSON.parse(JSON.stringify(st)), { frameNumber: numbers[st.frame] }); };
    el.aoevalViewer = { zoom: zoom, pan: pan, close: close };
  }

  // Opens a viewer (loads its data scripts, adds its panels); resolves when it is ready.
  function open(el) {
    if (el.aoevalViewer) return Promise.resolve(el);
    if (!el._aoevalOpening) {
      const srcs = [el.dataset.a, el.dataset.b].filter(Boolean);
      el._aoevalOpening = Promise.all(srcs.map(load)).then(function (recs) {
        Viewer(el, recs);
        el._aoevalOpening = null;
        return el;
      }, function (err) {
        el._aoevalOpening = null;
        tag('p', 'av-error', el, 'viewer: ' + err.message);
        throw err;
      });
    }
    return el._aoevalOpening;
  }

  // A sequence's video (CONTRACT §10: the estimate beside the reference, every kept frame at the
  // sequence's fps), drawn on a canvas from the viewer's own data (issue 42: an animated PNG held
  // the same frames a second time, 35 MB of the default report). Markup (reports/viewer.cpp
  // video_html): <div class="aoeval-video" data-a="REF.js" data-b="EST.js" data-fps="30">. It
  // loads its data when it first scrolls into view (a folded section's never does until unfolded,
  // so the page paints as fast), then loops while in view. Grey = sRGB(clamp(AO)), the mosaics'
  // panels; pixels either image leaves uncovered in the "not compared" grey.
  // element.aoevalOpen() loads it; element.aoevalVideoFrame(i) shows kept frame i and returns
  // {width, height, frame} (for tests: the canvas's pixels are then that frame's).
  const VIDEO_GAP = 4;
  function Video(el, recs) {
    const a = recs[0], b = recs[1], w = a.w, h = a.h, frames = a.frames || 1;
    const numbers = a.frame_numbers || Array.from({ length: frames }, (_, i) => i);
    const fps = Number(el.dataset.fps) || a.fps || 10;
    const bar = tag('div', 'av-bar', el), canvas = tag('canvas', 'av-video', el);
    canvas.width = 2 * w + VIDEO_GAP; canvas.height = h;
    const ctx = canvas.getContext('2d'), img = ctx.createImageData(canvas.width, h);
    img.data.fill(31);  // the mosaics' dark canvas (0.12)
    const playButton = tag('button', 'av-button', bar, 'pause'), label = tag('span', '', bar);
    playButton.type = 'button';
    let at = 0, timer = null;
    function show(i) {
      const shown = i, d = img.data, ma = plane(a, 'mask', shown), mb = plane(b, 'mask', shown);
      [plane(a, 'AO', shown), plane(b, 'AO', shown)].forEach(function (v, panel) {
        for (let y = 0; y < h; ++y)
          for (let x = 0; x < w; ++x) {
            const k = y * w + x, o = 4 * (y * canvas.width + x + panel * (w + VIDEO_GAP));
            const g = ma[k] && mb[k] ? Math.round(srgb(v[k])) : GREY;
            d[o] = d[o + 1] = d[o + 2] = g; d[o + 3] = 255;
          }
      });
      ctx.putImageData(img, 0, 0);
      label.textContent = ' reference | estimate, frame ' + numbers[shown] + ' (' + fps + ' frames per second)';
      return { width: canvas.width, height: h, frame: numbers[shown] };
    }
    function play(on) {
      if (timer) { clearInterval(timer); timer = null; }
      if (on) timer = setInterval(function () { at = (at + 1) % frames; show(at); }, 1000 / fps);
      playButton.textContent = on ? 'pause' : 'play';
    }
    playButton.addEventListener('click', function () { play(!timer); });
    show(0);
    el.aoevalVideoFrame = function (i) { play(false); at = i; return show(i); };
    el.aoevalVideoFrameCount = frames;
    return { play: play };
  }
  function openVideo(el) {
    if (!el._aoevalVideo)
      el._aoevalVideo = Promise.all([el.dataset.a, el.dataset.b].map(load)).then(function (recs) {
        el.aoevalVideo = Video(el, recs);
        return el;
      }, function (err) {
        tag('p', 'av-error', el, 'video: ' + err.message);
        throw err;
      });
    return el._aoevalVideo;
  }
  function initVideos() {
    const seen = 'IntersectionObserver' in window ? new IntersectionObserver(function (entries) {
      entries.forEach(function (e) {
        if (e.isIntersecting) openVideo(e.target).then(function (el) { el.aoevalVideo.play(true); }).catch(function () {});
        else if (e.target.aoevalVideo) e.target.aoevalVideo.play(false);
      });
    }) : null;
    document.querySelectorAll('.aoeval-video').forEach(function (el) {
      el.aoevalOpen = function () { return openVideo(el); };
      if (seen) seen.observe(el);
    });
  }

  // Every .aoeval-viewer gets an "open viewer" button; a click on its static image opens it too.
  function init() {
    initVideos();
    document.querySelectorAll('.aoeval-viewer').forEach(function (el) {
      el.aoevalOpen = function () { return open(el); };
      const b = document.createElement('button');
      b.type = 'button'; b.className = 'av-opener'; b.textContent = 'open viewer (zoom, probe, A/B)';
      b.addEventListener('click', function () { open(el).catch(function () {}); });
      el.insertBefore(b, el.firstChild);
      el.querySelectorAll('img').forEach(function (img) {
        img.addEventListener('click', function (ev) { ev.preventDefault(); open(el).catch(function () {}); });
      });
    });
  }
  if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', init);
  else init();
})();
