// SPDX-License-Identifier: GPL-3.0-or-later
// The interactive viewer of a `translucent compare` report: a technique (left) against a
// reference (right), shown by turns (flip), split by a slider, or as the false-colour error map the
// report wrote for the pair; zoom with the wheel, pan by dragging; the readout gives both images'
// linear RGB under the cursor and the relative error there.
//
// Plain script, no library and no network: the page is opened from file://, where a script may
// not fetch() the files beside it, so the data come as scripts too: viewer-data.js sets
// window.translucentViewerData (report.json "viewer", plus the masks) and each image's
// px-KEY.js calls translucentViewerPixels(key, width, height, base64 of float32 LE RGB), loaded
// when a pair first shows it. The images are drawn from those linear values with the report's
// tone map (exposure, then clamp to [0, 1], then 1/gamma: toneMapValue in io/image_io.h), so what
// is shown and what the readout says come from the same numbers.
(function () {
  'use strict';
  const data = window.translucentViewerData;
  const root = document.getElementById('viewer');
  if (!data || !root) return;
  const W = data.width, H = data.height;

  // ---- Pixels ------------------------------------------------------------------------------
  const pixels = {};   // key -> Float32Array, RGB rows from the top
  const waiting = {};  // key -> callbacks until its script has run

  function decodeBase64(text) {
    const bin = atob(text);
    const bytes = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; ++i) bytes[i] = bin.charCodeAt(i);
    return bytes;
  }

  window.translucentViewerPixels = function (key, width, height, base64) {
    const bytes = decodeBase64(base64);
    const view = new DataView(bytes.buffer);
    const values = new Float32Array(width * height * 3);
    for (let i = 0; i < values.length; ++i) values[i] = view.getFloat32(4 * i, true);
    pixels[key] = values;
    const callbacks = waiting[key] || [];
    delete waiting[key];
    callbacks.forEach(function (f) { f(); });
  };

  function load(key, done) {
    if (pixels[key]) { done(); return; }
    if (waiting[key]) { waiting[key].push(done); return; }
    waiting[key] = [done];
    const script = document.createElement('script');
    script.src = data.images[key].file;
    script.onerror = function () { setStatus('cannot load ' + data.images[key].file); };
    document.head.appendChild(script);
  }

  const masks = {};
  Object.keys(data.masks || {}).forEach(function (name) { masks[name] = decodeBase64(data.masks[name]); });

  // ---- Controls ----------------------------------------------------------------------------
  function el(tag, attrs, text) {
    const e = document.createElement(tag);
    Object.keys(attrs || {}).forEach(function (k) { e.setAttribute(k, attrs[k]); });
    if (text !== undefined) e.textContent = text;
    return e;
  }
  function labelled(text, control) {
    const l = el('label', {}, text + ' ');
    l.appendChild(control);
    return l;
  }

  const controls = el('div', { class: 'v-controls' });
  const testSel = el('select', { id: 'v-test' });
  const refSel = el('select', { id: 'v-reference' });
  const quantitySel = el('select', { id: 'v-quantity' });
  const modeSel = el('select', { id: 'v-mode' });
  [['flip', 'flip'], ['slider', 'slider'], ['error', 'error map']].forEach(function (m) {
    modeSel.appendChild(el('option', { value: m[0] }, m[1]));
  });
  const mapSel = el('select', { id: 'v-map' });
  [['relative', 'relative difference'], ['z', 'z-score'], ['flip', 'FLIP']].forEach(function (m) {
    mapSel.appendChild(el('option', { value: m[0] }, m[1]));
  });
  const flipBtn = el('button', { id: 'v-flip', type: 'button' }, 'flip (F)');
  const split = el('input', { id: 'v-split', type: 'range', min: '0', max: '1000', value: '500' });
  const resetBtn = el('button', { id: 'v-reset', type: 'button' }, 'fit (0)');
  controls.appendChild(labelled('technique', testSel));
  controls.appendChild(labelled('reference', refSel));
  controls.appendChild(labelled('quantity', quantitySel));
  controls.appendChild(labelled('mode', modeSel));
  controls.appendChild(labelled('map', mapSel));
  controls.appendChild(flipBtn);
  controls.appendChild(labelled('split', split));
  controls.appendChild(resetBtn);

  // The canvas: the image fitted into at most 720 x 540 CSS pixels, at least 4 pixels a pixel
  // for small images; its buffer is its CSS size (the style sheet keeps it so).
  const fit0 = Math.max(1, Math.min(720 / W, 540 / H));
  const canvas = el('canvas', { id: 'v-canvas' });
  canvas.width = Math.round(W * fit0);
  canvas.height = Math.round(H * fit0);
  canvas.style.width = canvas.width + 'px';
  canvas.style.height = canvas.height + 'px';
  const ctx = canvas.getContext('2d');
  const stage = el('div', { class: 'v-stage' });
  stage.appendChild(canvas);
  const caption = el('div', { id: 'v-caption', class: 'v-caption' });
  stage.appendChild(caption);
  const bar = el('img', { class: 'v-bar', alt: 'colour bar' });
  stage.appendChild(bar);

  const readout = el('div', { id: 'v-readout', class: 'v-readout' });
  const side = el('div');
  side.appendChild(readout);
  side.appendChild(el('p', { class: 'v-help' },
    'Wheel: zoom about the cursor. Drag: pan. Click or F: flip between the two images (flip mode); ' +
    'click: move the split (slider mode). 0: fit. 1, 2, 3: flip, slider, error map. ' +
    'The readout gives the linear values (not tone mapped) of the pixel under the cursor.'));
  root.appendChild(controls);
  root.appendChild(stage);
  root.appendChild(side);

  // ---- State -------------------------------------------------------------------------------
  const state = { test: null, reference: null, pair: null, mode: 'flip', map: 'relative',
    showRight: false, split: 0.5 };
  const view = { scale: 1, ox: 0, oy: 0 };
  let fitScale = 1;
  const offscreen = {};  // image key -> canvas of the tone-mapped image
  const mapImages = {};  // file -> Image
  let lastPointer = null;  // canvas coordinates of the cursor, while over the canvas

  function setStatus(text) { caption.textContent = text; }

  function pairsOf(test, reference) {
    return data.pairs.filter(function (p) {
      return p.test === test && (reference === undefined || p.reference === reference);
    });
  }
  function fill(select, values, labels, keep) {
    select.textContent = '';
    values.forEach(function (v, i) { select.appendChild(el('option', { value: v }, labels[i])); });
    select.value = values.indexOf(keep) >= 0 ? keep : values[0];
  }
  function unique(list) { return list.filter(function (v, i) { return list.indexOf(v) === i; }); }
  function quantityLabel(p) {
    const names = { exitance: 'exitance B', radiance: 'radiance L', cone_radiance: 'true radiance (cone)' };
    return (names[p.quantity] || p.quantity) + (p.convention ? ' (' + p.convention + ')' : '');
  }

  function updateSelectors() {
    const tests = data.tests.filter(function (t) { return pairsOf(t).length > 0; });
    fill(testSel, tests, tests.map(function (t) { return t === 'model' ? 'model reference' : t; }),
      state.test);
    state.test = testSel.value;
    const refs = unique(pairsOf(state.test).map(function (p) { return p.reference; }));
    const preferred = state.reference || (refs.indexOf('physical') >= 0 ? 'physical' : refs[0]);
    fill(refSel, refs, refs.map(function (r) { return r + ' reference'; }), preferred);
    state.reference = refSel.value;
    const pairs = pairsOf(state.test, state.reference);
    const keys = pairs.map(function (p) { return p.quantity + '/' + p.convention; });
    const keep = state.pair ? state.pair.quantity + '/' + state.pair.convention : 'radiance/';
    let chosen = keys.indexOf(keep);
    if (chosen < 0) {
      chosen = pairs.findIndex(function (p) { return p.quantity === (state.pair ? state.pair.quantity : 'radiance'); });
    }
    fill(quantitySel, keys, pairs.map(quantityLabel), keys[Math.max(0, chosen)]);
    state.pair = pairs[keys.indexOf(quantitySel.value)];
    showPair();
  }

  function toneMapped(key) {
    if (offscreen[key]) return offscreen[key];
    const img = data.images[key], v = pixels[key];
    const c = document.createElement('canvas');
    c.width = img.width;
    c.height = img.height;
    const c2 = c.getContext('2d');
    const out = c2.createImageData(img.width, img.height);
    const k = Math.pow(2, img.exposure), g = 1 / data.gamma;
    for (let p = 0; p < img.width * img.height; ++p) {
      for (let ch = 0; ch < 3; ++ch) {
        let x = v[3 * p + ch] * k;
        x = x > 0 ? Math.pow(Math.min(x, 1), g) : 0;  // also NaN to 0
        out.data[4 * p + ch] = Math.round(255 * x);
      }
      out.data[4 * p + 3] = 255;
    }
    c2.putImageData(out, 0, 0);
    offscreen[key] = c;
    return c;
  }

  function mapImage(file) {
    if (!mapImages[file]) {
      const im = new Image();
      im.onload = draw;
      im.src = file;  // drawing it taints the canvas, which is never read back
      mapImages[file] = im;
    }
    return mapImages[file];
  }

  function ready() {
    const p = state.pair;
    return p && pixels[p.left] && pixels[p.right];
  }

  function showPair() {
    const p = state.pair;
    if (!p) return;
    setStatus('loading ' + data.images[p.left].file + ' and ' + data.images[p.right].file + ' …');
    let pending = 2;
    const done = function () {
      if (--pending > 0 || state.pair !== p) return;
      root.setAttribute('data-ready', p.left + '|' + p.right);
      draw();
      updateReadout();
    };
    root.removeAttribute('data-ready');
    load(p.left, done);
    load(p.right, done);
  }

  // ---- Drawing -----------------------------------------------------------------------------
  function fitView() {
    fitScale = Math.min(canvas.width / W, canvas.height / H);
    view.scale = fitScale;
    view.ox = (canvas.width - W * fitScale) / 2;
    view.oy = (canvas.height - H * fitScale) / 2;
  }

  function draw() {
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.fillStyle = '#333';
    ctx.fillRect(0, 0, canvas.width, canvas.height);
    const p = state.pair;
    flipBtn.disabled = state.mode !== 'flip';
    split.disabled = state.mode !== 'slider';
    mapSel.disabled = state.mode !== 'error';
    bar.style.display = state.mode === 'error' ? '' : 'none';
    if (!ready()) return;
    ctx.imageSmoothingEnabled = false;
    const place = function () { ctx.setTransform(view.scale, 0, 0, view.scale, view.ox, view.oy); };
    const leftName = data.images[p.left].label, rightName = data.images[p.right].label;
    if (state.mode === 'error') {
      const file = p.maps[state.map];
      bar.src = data.bars[state.map];
      const im = mapImage(file);
      place();
      if (im.complete && im.naturalWidth) ctx.drawImage(im, 0, 0, W, H);
      setStatus('error map (' + mapSel.options[mapSel.selectedIndex].text + ') of ' + leftName +
        ' against ' + rightName + '; grey: not compared');
    } else if (state.mode === 'flip') {
      place();
      ctx.drawImage(toneMapped(state.showRight ? p.right : p.left), 0, 0);
      setStatus('showing ' + (state.showRight ? 'right: ' + rightName : 'left: ' + leftName));
    } else {
      place();
      ctx.drawImage(toneMapped(p.left), 0, 0);
      const x = state.split * canvas.width;
      ctx.save();
      ctx.setTransform(1, 0, 0, 1, 0, 0);
      ctx.beginPath();
      ctx.rect(x, 0, canvas.width - x, canvas.height);
      ctx.clip();
      place();
      ctx.drawImage(toneMapped(p.right), 0, 0);
      ctx.restore();
      ctx.setTransform(1, 0, 0, 1, 0, 0);
      ctx.fillStyle = '#ff0';
      ctx.fillRect(Math.round(x) - 1, 0, 2, canvas.height);
      setStatus('left of the line: ' + leftName + '; right: ' + rightName);
    }
    root.setAttribute('data-showing', state.mode === 'flip' ? (state.showRight ? 'right' : 'left') : state.mode);
  }

  // ---- Readout -----------------------------------------------------------------------------
  function fmt(v) {
    if (!isFinite(v)) return String(v);
    return v === 0 ? '0' : v.toPrecision(7);
  }
  function pct(v) { return isFinite(v) ? (100 * v).toFixed(3) + '%' : '–'; }

  // The image pixel under a canvas point (x, y in CSS pixels of the canvas), or null.
  function pixelAt(x, y) {
    const ix = Math.floor((x - view.ox) / view.scale), iy = Math.floor((y - view.oy) / view.scale);
    return ix >= 0 && iy >= 0 && ix < W && iy < H ? { x: ix, y: iy } : null;
  }

  function updateReadout() {
    readout.textContent = '';
    const p = state.pair;
    if (!ready()) { readout.appendChild(el('p', {}, 'loading …')); return; }
    const at = lastPointer ? pixelAt(lastPointer.x, lastPointer.y) : null;
    if (!at) {
      readout.appendChild(el('p', {}, 'Move the cursor over the image.'));
      readout.removeAttribute('data-values');
      return;
    }
    const i = at.y * W + at.x;
    const a = Array.from(pixels[p.left].subarray(3 * i, 3 * i + 3));
    const b = Array.from(pixels[p.right].subarray(3 * i, 3 * i + 3));
    const rel = a.map(function (v, c) { return b[c] !== 0 ? (v - b[c]) / b[c] : NaN; });
    const sa = a[0] + a[1] + a[2], sb = b[0] + b[1] + b[2];
    const relSum = sb !== 0 ? (sa - sb) / sb : NaN;
    const mask = masks[p.mask];
    const compared = !mask || mask[i] !== 0;
    readout.appendChild(el('p', {}, 'pixel '))
      .appendChild(el('b', { id: 'v-pixel' }, '(' + at.x + ', ' + at.y + ')'));
    const table = el('table', { id: 'v-values' });
    const head = el('tr');
    ['', 'R', 'G', 'B'].forEach(function (h) { head.appendChild(el('th', {}, h)); });
    table.appendChild(head);
    const row = function (id, name, values, f) {
      const tr = el('tr', { id: id });
      tr.appendChild(el('th', { class: 'l' }, name));
      values.forEach(function (v) { tr.appendChild(el('td', {}, f(v))); });
      table.appendChild(tr);
    };
    row('v-left', 'left: ' + data.images[p.left].label, a, fmt);
    row('v-right', 'right: ' + data.images[p.right].label, b, fmt);
    row('v-rel', 'relative error (left − right) / right', rel, pct);
    readout.appendChild(table);
    readout.appendChild(el('p', { id: 'v-relsum' },
      'relative error of R + G + B (the relative difference map): ' + pct(relSum)));
    if (!compared) {
      readout.appendChild(el('p', { class: 'v-outside' },
        'outside the ' + p.mask.replace('_', ' ') + ' mask: not in the metrics or the error maps'));
    }
    // The same numbers unrounded, for scripts and tests.
    readout.setAttribute('data-values', JSON.stringify({ x: at.x, y: at.y, left: a, right: b,
      relative: rel, relative_sum: relSum, compared: compared, left_key: p.left, right_key: p.right }));
  }

  // ---- Events ------------------------------------------------------------------------------
  function canvasPoint(e) {
    const r = canvas.getBoundingClientRect();
    return { x: (e.clientX - r.left) * canvas.width / r.width, y: (e.clientY - r.top) * canvas.height / r.height };
  }
  let drag = null;

  canvas.addEventListener('wheel', function (e) {
    e.preventDefault();
    const q = canvasPoint(e);
    const factor = Math.exp(-e.deltaY * (e.deltaMode === 1 ? 0.05 : 0.002));
    const s = Math.min(Math.max(view.scale * factor, fitScale / 2), fitScale * 256);
    // Zoom about the cursor: the image point under it stays there.
    view.ox = q.x - (q.x - view.ox) * s / view.scale;
    view.oy = q.y - (q.y - view.oy) * s / view.scale;
    view.scale = s;
    lastPointer = q;
    draw();
    updateReadout();
  }, { passive: false });

  canvas.addEventListener('mousedown', function (e) {
    if (e.button !== 0) return;
    drag = { start: canvasPoint(e), ox: view.ox, oy: view.oy, moved: false };
    e.preventDefault();
  });
  window.addEventListener('mousemove', function (e) {
    if (drag) {
      const q = canvasPoint(e);
      const dx = q.x - drag.start.x, dy = q.y - drag.start.y;
      if (Math.abs(dx) + Math.abs(dy) > 3) drag.moved = true;
      if (drag.moved) {
        canvas.classList.add('dragging');
        view.ox = drag.ox + dx;
        view.oy = drag.oy + dy;
        draw();
      }
    }
  });
  window.addEventListener('mouseup', function (e) {
    if (!drag) return;
    const wasClick = !drag.moved;
    drag = null;
    canvas.classList.remove('dragging');
    if (!wasClick || e.target !== canvas) return;
    if (state.mode === 'flip') {
      state.showRight = !state.showRight;
    } else if (state.mode === 'slider') {
      state.split = Math.min(Math.max(canvasPoint(e).x / canvas.width, 0), 1);
      split.value = String(Math.round(1000 * state.split));
    }
    draw();
  });
  canvas.addEventListener('mousemove', function (e) {
    lastPointer = canvasPoint(e);
    updateReadout();
  });
  canvas.addEventListener('mouseleave', function () {
    lastPointer = null;
    updateReadout();
  });

  function setMode(mode) {
    state.mode = mode;
    modeSel.value = mode;
    draw();
  }
  document.addEventListener('keydown', function (e) {
    const t = e.target;
    if (e.ctrlKey || e.metaKey || e.altKey) return;
    if (t && (t.tagName === 'INPUT' || t.tagName === 'SELECT' || t.tagName === 'TEXTAREA')) return;
    if (e.key === 'f' || e.key === 'F') {
      if (state.mode !== 'flip') setMode('flip');
      state.showRight = !state.showRight;
      draw();
    } else if (e.key === '0') {
      fitView();
      draw();
      updateReadout();
    } else if (e.key === '1' || e.key === '2' || e.key === '3') {
      setMode(['flip', 'slider', 'error'][Number(e.key) - 1]);
    }
  });

  testSel.addEventListener('change', function () { state.test = testSel.value; state.showRight = false; updateSelectors(); });
  refSel.addEventListener('change', function () { state.reference = refSel.value; updateSelectors(); });
  quantitySel.addEventListener('change', function () {
    state.pair = pairsOf(state.test, state.reference)[quantitySel.selectedIndex];
    showPair();
  });
  modeSel.addEventListener('change', function () { setMode(modeSel.value); });
  mapSel.addEventListener('change', function () { state.map = mapSel.value; draw(); });
  flipBtn.addEventListener('click', function () { state.showRight = !state.showRight; draw(); });
  split.addEventListener('input', function () { state.split = Number(split.value) / 1000; draw(); });
  resetBtn.addEventListener('click', function () { fitView(); draw(); updateReadout(); });

  // For scripts (and the report's browser test): the state and the view, read only.
  window.translucentViewer = {
    state: function () { return { test: state.test, reference: state.reference, mode: state.mode,
      map: state.map, showRight: state.showRight, split: state.split,
      pair: state.pair ? { quantity: state.pair.quantity, convention: state.pair.convention,
        left: state.pair.left, right: state.pair.right } : null }; },
    view: function () { return { scale: view.scale, ox: view.ox, oy: view.oy, fit: fitScale }; }
  };

  fitView();
  if (data.tests.length === 0) {
    setStatus('No technique rendered and no pair of references to show.');
    draw();
    return;
  }
  updateSelectors();
})();
