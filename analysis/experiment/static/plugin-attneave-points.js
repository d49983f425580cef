/*
 * jsPsych 8 plugins of the attneave point-selection task (written by `attneave experiment --jspsych`).
 *
 *   jsPsychAttneavePoints     trial_type "attneave-points": one stimulus; the participant clicks points
 *                             on its contour. Data: one row per stimulus with
 *                               stimulus_id, participant, clicks = [{x, y, rt}, ...]
 *                             x, y in the stimulus IMAGE's pixels (pixel centres at integers, y down)
 *                             whatever its CSS size; rt in ms from the first frame showing the image.
 *                             `attneave analyze` reads jsPsych.data.get().csv() or .json() as they are.
 *   jsPsychAttneavePractice   the same task, trial_type "attneave-points-practice" (analyze sets it aside).
 *   jsPsychAttneaveScreen     trial_type "attneave-screen": a text screen (instructions, break, ...), the
 *                             participant id screen or the credit-card calibration.
 *
 * PAGE CONTRACT (as the standalone page's, see task.js): while a stimulus is shown, #stimulus is the
 * <img> with its id in data-stimulus-id; #next ends the trial once its clicks are in (space bar too);
 * #undo removes the last click (Backspace, Z); a screen is #screen with data-screen naming it.
 *
 * Plain ES2017, no dependencies but jsPsych 8 (the global jsPsychModule of jspsych.js).
 */
var jsPsychAttneavePoints = (function (jspsych) {
  'use strict';
  var P = jspsych.ParameterType;

  var info = {
    name: 'attneave-points',
    version: '1.0.0',
    parameters: {
      /** the image file */
      stimulus: { type: P.IMAGE, default: undefined },
      /** the stimulus id (recorded, and data-stimulus-id of #stimulus) */
      stimulus_id: { type: P.STRING, default: undefined },
      /** the image's size in pixels (the click coordinates' frame) */
      image_width: { type: P.INT, default: undefined },
      image_height: { type: P.INT, default: undefined },
      /** CSS px of the image's width (its height in proportion); shrunk to fit the window */
      css_width: { type: P.FLOAT, default: null },
      /** fewest clicks before #next is enabled; most clicks taken (null: no bound) */
      min_clicks: { type: P.INT, default: 1 },
      max_clicks: { type: P.INT, default: null },
      undo: { type: P.BOOL, default: true },
      /** a fixation cross this long before the image (0: none) */
      fixation_ms: { type: P.INT, default: 0 },
      /** shown at the bottom left ("Trial 3 of 40") */
      progress: { type: P.STRING, default: '' },
      /** recorded as they are */
      participant: { type: P.STRING, default: null },
      trial: { type: P.INT, default: null },
      condition: { type: P.STRING, default: '' },
      parent_id: { type: P.STRING, default: '' },
      list: { type: P.INT, default: null },
      px_per_deg: { type: P.FLOAT, default: null },
      px_per_mm: { type: P.FLOAT, default: null },
      viewing_distance_cm: { type: P.FLOAT, default: null }
    },
    data: {
      stimulus_id: { type: P.STRING },
      participant: { type: P.STRING },
      /** [{x, y, rt}]: image pixels, ms from the image's first frame */
      clicks: { type: P.COMPLEX, array: true, nested: { x: { type: P.FLOAT }, y: { type: P.FLOAT }, rt: { type: P.FLOAT } } },
      trial: { type: P.INT },
      condition: { type: P.STRING },
      parent_id: { type: P.STRING },
      list: { type: P.INT },
      shown_w: { type: P.FLOAT },
      shown_h: { type: P.FLOAT },
      px_per_deg: { type: P.FLOAT },
      px_per_mm: { type: P.FLOAT },
      viewing_distance_cm: { type: P.FLOAT },
      screen_w: { type: P.INT },
      screen_h: { type: P.INT },
      device_pixel_ratio: { type: P.FLOAT },
      pointer_type: { type: P.STRING },
      /** ms from the image's first frame to #next */
      rt: { type: P.FLOAT }
    }
  };

  function el(tag, attrs, children) {
    var node = document.createElement(tag);
    Object.keys(attrs || {}).forEach(function (k) {
      if (k === 'text') node.textContent = attrs[k]; else node.setAttribute(k, attrs[k]);
    });
    (children || []).forEach(function (c) { node.appendChild(c); });
    return node;
  }

  function round(v, digits) {
    var f = Math.pow(10, digits);
    return Math.round(v * f) / f;
  }

  class AttneavePointsPlugin {
    constructor(jsPsych) {
      this.jsPsych = jsPsych;
    }

    trial(display_element, trial) {
      var jsPsych = this.jsPsych;
      var maxClicks = trial.max_clicks === null ? Infinity : trial.max_clicks;
      // the whole window, as the standalone page: the stimulus's size must not depend on jsPsych's layout
      var img = el('img', { id: 'stimulus', alt: 'shape', draggable: 'false' });
      var marks = el('div', { 'class': 'marks', id: 'marks' });
      var frame = el('div', { 'class': 'frame', id: 'frame', hidden: '' }, [img, marks]);
      var fixation = el('div', { 'class': 'fixation', id: 'fixation', hidden: '', text: '+' });
      var stage = el('section', { 'class': 'stage', id: 'stage' }, [fixation, frame]);
      var prompt = el('span', { 'class': 'prompt', id: 'prompt' });
      var undoBtn = el('button', { type: 'button', id: 'undo', text: 'Undo', hidden: '' });
      var nextBtn = el('button', { type: 'button', id: 'next', text: 'Next', disabled: '' });
      var controls = el('nav', { 'class': 'controls', id: 'controls' },
        [el('span', { 'class': 'progress', id: 'progress', text: trial.progress }), prompt, undoBtn, nextBtn]);
      var app = el('div', { 'class': 'attneave-app' }, [stage, controls]);
      display_element.innerHTML = '';
      display_element.appendChild(app);

      var clicks = [];
      var onset = null, shown = false, last = null;

      function update() {
        var n = clicks.length;
        nextBtn.disabled = !shown || n < trial.min_clicks;
        undoBtn.disabled = n === 0;
        if (trial.min_clicks === trial.max_clicks) {
          var left = trial.min_clicks - n;
          prompt.textContent = left > 0 ? 'Click ' + left + ' more point' + (left > 1 ? 's' : '') : 'Press Next';
        } else {
          prompt.textContent = n < trial.min_clicks
            ? 'Click at least ' + trial.min_clicks + ' point' + (trial.min_clicks > 1 ? 's' : '') + ' (' + n + ' so far)'
            : n + ' point' + (n > 1 ? 's' : '') + ' — press Next when done';
        }
      }
      function fit() {
        var w = trial.css_width === null ? trial.image_width : trial.css_width;
        var h = w * trial.image_height / trial.image_width;
        var room = Math.min((stage.clientWidth - 8) / w, (stage.clientHeight - 8) / h, 1);
        img.style.width = (w * room) + 'px';
        img.style.height = (h * room) + 'px';
      }
      function undo() {
        if (!trial.undo || !clicks.length) return;
        clicks.pop();
        if (marks.lastChild) marks.removeChild(marks.lastChild);
        update();
      }
      function end() {
        if (nextBtn.disabled) return;
        var now = performance.now();
        window.removeEventListener('resize', refit);
        document.removeEventListener('keydown', onKey);
        img.removeAttribute('data-stimulus-id');
        var scr = window.screen || {};
        var data = {
          stimulus_id: trial.stimulus_id,
          participant: trial.participant,
          clicks: clicks.map(function (c) { return { x: round(c.x, 3), y: round(c.y, 3), rt: Math.round(c.rt) }; }),
          trial: trial.trial,
          condition: trial.condition,
          parent_id: trial.parent_id,
          list: trial.list,
          shown_w: last ? round(last.width, 3) : null,
          shown_h: last ? round(last.height, 3) : null,
          px_per_deg: trial.px_per_deg === null ? null : round(trial.px_per_deg, 4),
          px_per_mm: trial.px_per_mm === null ? null : round(trial.px_per_mm, 4),
          viewing_distance_cm: trial.viewing_distance_cm,
          screen_w: scr.width,
          screen_h: scr.height,
          device_pixel_ratio: window.devicePixelRatio || 1,
          pointer_type: clicks.length ? clicks[clicks.length - 1].pointer : '',
          rt: onset === null ? null : Math.round(now - onset)
        };
        display_element.innerHTML = '';
        jsPsych.finishTrial(data);
      }
      function onKey(e) {
        var typing = e.target && (e.target.tagName === 'INPUT' || e.target.tagName === 'TEXTAREA');
        if (typing) return;
        if (e.key === ' ' || e.code === 'Space') {
          e.preventDefault();
          if (!e.repeat) end();
        } else if (e.key === 'Backspace' || e.key === 'z' || e.key === 'Z') {
          e.preventDefault();
          undo();
        }
      }
      function refit() { if (shown) fit(); }

      img.addEventListener('pointerdown', function (e) {
        if (!shown || !e.isPrimary || e.button !== 0) return;
        e.preventDefault();
        if (clicks.length >= maxClicks) return;
        var now = performance.now();
        var rect = img.getBoundingClientRect();
        last = rect;
        var p = window.attneave && window.attneave.toImagePx
          ? window.attneave.toImagePx(e.clientX, e.clientY, rect, img.naturalWidth || trial.image_width, img.naturalHeight || trial.image_height)
          : { x: (e.clientX - rect.left) * trial.image_width / rect.width - 0.5, y: (e.clientY - rect.top) * trial.image_height / rect.height - 0.5 };
        clicks.push({ x: p.x, y: p.y, rt: onset === null ? 0 : now - onset, pointer: e.pointerType || 'mouse' });
        var m = el('div', { 'class': 'mark' });
        m.style.left = (100 * (e.clientX - rect.left) / rect.width) + '%';
        m.style.top = (100 * (e.clientY - rect.top) / rect.height) + '%';
        marks.appendChild(m);
        update();
      });
      img.addEventListener('contextmenu', function (e) { e.preventDefault(); });
      undoBtn.addEventListener('click', function () { undoBtn.blur(); undo(); });
      nextBtn.addEventListener('click', function () { nextBtn.blur(); end(); });
      document.addEventListener('keydown', onKey);
      window.addEventListener('resize', refit);

      function show() {
        fixation.hidden = true;
        shown = true;
        img.setAttribute('data-stimulus-id', trial.stimulus_id);
        undoBtn.hidden = !trial.undo;
        update();
        fit();
        frame.hidden = false;
        last = img.getBoundingClientRect();
        requestAnimationFrame(function () { onset = performance.now(); });
      }
      img.onerror = function () {
        prompt.textContent = 'Could not load image ' + trial.stimulus + '.';
      };
      img.onload = function () {
        img.onload = null;
        if (trial.fixation_ms > 0) {
          fixation.hidden = false;
          jsPsych.pluginAPI.setTimeout(show, trial.fixation_ms);
        } else show();
      };
      update();
      img.src = trial.stimulus;
    }
  }
  AttneavePointsPlugin.info = info;
  return AttneavePointsPlugin;
})(jsPsychModule);

/** Practice trials: the same task under another trial_type, so that analysis sets them aside. */
var jsPsychAttneavePractice = (function () {
  'use strict';
  class AttneavePracticePlugin extends jsPsychAttneavePoints {}
  AttneavePracticePlugin.info = Object.assign({}, jsPsychAttneavePoints.info, { name: 'attneave-points-practice' });
  return AttneavePracticePlugin;
})();

var jsPsychAttneaveScreen = (function (jspsych) {
  'use strict';
  var P = jspsych.ParameterType;
  var CARD_WIDTH_MM = 85.60;  // ISO/IEC 7810 ID-1 (credit card)
  var ID = /^[A-Za-z0-9][A-Za-z0-9_.@-]{0,63}$/;

  var info = {
    name: 'attneave-screen',
    version: '1.0.0',
    parameters: {
      /** instructions, break, practice-end, participant, calibration or error */
      screen: { type: P.STRING, default: 'instructions' },
      title: { type: P.STRING, default: '' },
      /** paragraphs separated by blank lines */
      text: { type: P.STRING, default: '' },
      /** calibration: the distance asked for */
      distance_cm: { type: P.FLOAT, default: 57 }
    },
    data: {
      screen: { type: P.STRING },
      /** participant: the id typed */
      participant_input: { type: P.STRING },
      /** calibration: the card's width in CSS px and the CSS px per mm it gives */
      card_width_px: { type: P.FLOAT },
      px_per_mm: { type: P.FLOAT }
    }
  };

  function el(tag, attrs, children) {
    var node = document.createElement(tag);
    Object.keys(attrs || {}).forEach(function (k) {
      if (k === 'text') node.textContent = attrs[k]; else node.setAttribute(k, attrs[k]);
    });
    (children || []).forEach(function (c) { node.appendChild(c); });
    return node;
  }
  function paragraphs(text) {
    return String(text).split(/\n\s*\n/).filter(function (p) { return p.trim(); })
      .map(function (p) { return el('p', { text: p.trim() }); });
  }

  class AttneaveScreenPlugin {
    constructor(jsPsych) {
      this.jsPsych = jsPsych;
    }

    trial(display_element, trial) {
      var jsPsych = this.jsPsych;
      var nodes = trial.title ? [el('h1', { text: trial.title })] : [];
      nodes = nodes.concat(paragraphs(trial.text));
      var data = { screen: trial.screen };
      var ready = function () { return true; };
      var collect = function () {};
      if (trial.screen === 'participant') {
        var input = el('input', { type: 'text', id: 'participant-input', autocomplete: 'off', 'aria-label': 'participant id' });
        var why = el('p', { id: 'participant-error', 'class': 'error' });
        nodes.push(input, why);
        ready = function () { return ID.test(input.value.trim()); };
        collect = function () { data.participant_input = input.value.trim(); };
        input.addEventListener('input', function () {
          var v = input.value.trim();
          why.textContent = v === '' || ID.test(v) ? '' : 'A participant id is 1 to 64 letters, digits, _ . @ or -, beginning with a letter or digit.';
          nextBtn.disabled = !ready();
        });
      } else if (trial.screen === 'calibration') {
        var width = Math.min(323.5, (window.innerWidth || 400) - 60);
        var card = el('div', { 'class': 'card', id: 'card' });
        var range = el('input', { type: 'range', id: 'card-size', min: '100', max: '1200', step: '0.5', value: String(width), 'aria-label': 'card size' });
        var minus = el('button', { type: 'button', id: 'card-smaller', text: '−' });
        var plus = el('button', { type: 'button', id: 'card-larger', text: '+' });
        var set = function (w) {
          width = Math.max(60, Math.min(2000, w));
          card.style.width = width + 'px';
          range.value = String(width);
        };
        range.addEventListener('input', function () { set(Number(range.value)); });
        minus.addEventListener('click', function () { set(width - 1); });
        plus.addEventListener('click', function () { set(width + 1); });
        set(width);
        nodes = [el('h1', { text: 'Screen size' }),
          el('p', { text: 'Hold a credit card (or any card of that size: bank card, ID card) flat against the screen, over the picture below. Use the slider or the − and + buttons until the picture is exactly as wide as the card.' }),
          el('div', { 'class': 'card-area' }, [card]),
          el('div', { 'class': 'card-controls' }, [minus, range, plus]),
          el('p', { text: 'Then sit about ' + Math.round(trial.distance_cm) + ' cm (an arm\'s length) from the screen and keep that distance.' })];
        collect = function () {
          data.card_width_px = card.getBoundingClientRect().width;
          data.px_per_mm = data.card_width_px / CARD_WIDTH_MM;
        };
      }
      var screen = el('section', { id: 'screen', 'class': 'screen', 'data-screen': trial.screen }, [el('div', { 'class': 'panel' }, nodes)]);
      var nextBtn = el('button', { type: 'button', id: 'next', text: 'Next' });
      var app = el('div', { 'class': 'attneave-app' }, [screen, el('nav', { 'class': 'controls' }, [el('span', { 'class': 'prompt' }), nextBtn])]);
      display_element.innerHTML = '';
      display_element.appendChild(app);
      if (trial.screen === 'error') { nextBtn.hidden = true; return; }
      nextBtn.disabled = !ready();
      var start = performance.now();
      function end() {
        if (nextBtn.disabled) return;
        document.removeEventListener('keydown', onKey);
        collect();
        data.rt = Math.round(performance.now() - start);
        display_element.innerHTML = '';
        jsPsych.finishTrial(data);
      }
      function onKey(e) {
        var typing = e.target && e.target.tagName === 'INPUT' && e.target.type === 'text';
        if ((e.key === ' ' || e.code === 'Space') && !typing) { e.preventDefault(); if (!e.repeat) end(); }
        else if (e.key === 'Enter' && typing) { e.preventDefault(); end(); }
      }
      nextBtn.addEventListener('click', function () { nextBtn.blur(); end(); });
      document.addEventListener('keydown', onKey);
      if (input) input.focus();
    }
  }
  AttneaveScreenPlugin.info = info;
  return AttneaveScreenPlugin;
})(jsPsychModule);
