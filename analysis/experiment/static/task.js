/*
 * attneave point-selection task (written by `attneave experiment`).
 * Plain ES2017, no dependencies, no requests: runs from file:// and any static host.
 *
 * PAGE CONTRACT (stable; hosts, scripts and tests rely on it)
 *   URL parameters
 *     ?participant=ID   participant id (or the parameter --participant-param names, e.g.
 *                       PROLIFIC_PID, id, workerId; else PROLIFIC_PID=, else a screen asks); an id
 *                       must match PARTICIPANT_ID: 1-64 letters, digits, _ . @ -, beginning
 *                       with a letter or digit (Prolific, SONA and MTurk ids do); another is
 *                       refused with a message (the screen "error", or on the id screen)
 *     ?list=N           counterbalancing list 1..K (else derived from the participant id)
 *     ?px_per_mm=F      CSS px per mm: skips the card calibration
 *     ?px_per_deg=F     CSS px per degree: skips the calibration and the viewing distance
 *     ?distance_cm=F    viewing distance used with px_per_mm or the calibration
 *     ?fresh=1          forget this participant's saved progress and start again
 *   Elements
 *     #next             advances every screen before, between and after trials, and ends
 *                       a trial once its clicks are in (disabled until then). Space = #next.
 *     #stimulus         the displayed stimulus (an <img>); its id is in data-stimulus-id.
 *                       Clicks/taps are pointer events on it (mouse, pen and touch).
 *     #undo             removes the last click of the trial (also Backspace or Z).
 *     #download         on the final screen, a link whose href holds the CSV (data: URL).
 *     #submit-status    with --submit-url: data-state = pending | ok | failed.
 *     #screen           the text screen; data-screen names it while shown: participant,
 *                       calibration, instructions, resume, break, practice-end, end, error.
 *   Data
 *     window.attneaveData   the rows so far (objects with the CSV's columns), one per click,
 *                           main trials only (practice rows are in window.attneavePractice).
 *     CSV columns: participant, stimulus_id, x, y, click, trial, rt_ms, condition, list,
 *       parent_id, shown_w, shown_h, px_per_deg, px_per_mm, viewing_distance_cm, screen_w,
 *       screen_h, device_pixel_ratio, pointer_type, user_agent, timestamp
 *     A text cell beginning with = + - @ tab or CR (a formula to a spreadsheet) is written
 *       with a ' before it (OWASP's rule against CSV injection); numbers are written as they
 *       are. `attneave analyze` removes that ' when it reads the file.
 *     x, y are in the stimulus IMAGE's pixels (x = column, y = row, y down, pixel centres at
 *     integers: pixel i spans [i - 0.5, i + 0.5]) whatever the CSS size:
 *       x = (clientX - rect.left) * naturalWidth / rect.width - 0.5
 *     so `attneave analyze` reads the CSV as it is. Sizes in px are CSS px.
 *   Progress: after every main trial the rows so far and the place in the trial order are
 *     kept in the browser's localStorage (key attneave:<hash of the page's settings>:<id>).
 *     Opening the page again with the same participant id (a reload, a closed tab) shows the
 *     screen "resume" and goes on with the next trial, or, once finished, the end screen
 *     with the download again. Once a --submit-url POST succeeded the rows are removed and only
 *     a note that the participant is done stays: opening the page again shows the end screen
 *     with #submit-status ok and no #download (?fresh=1 starts again). While trials are under
 *     way, leaving the page asks the browser's "leave site?" question. The same participant in
 *     two tabs: the tab that keeps a trial first goes on, the other shows the screen "error".
 *   Recruitment: the parameters --participant-param records (Prolific's STUDY_ID and SESSION_ID,
 *     MTurk's assignmentId and hitId) are columns after timestamp. With --completion-url the page
 *     sends the participant there once the data are submitted (or, with neither --submit-url nor
 *     JATOS, offers the link #complete beside #download).
 *   JATOS (--jatos): jatos.js beside the page; the page starts in jatos.onLoad, reads the study
 *     link's parameters from jatos.urlQueryParameters too, takes completion_url from the component's
 *     (or study's) JSON input, submits the CSV with jatos.submitResultData (4 attempts; #submit-status)
 *     and then calls jatos.endStudyAndRedirect(completion URL) or jatos.endStudy(); no #download
 *     unless the submission failed.
 *   Trial order: mulberry32 seeded with FNV-1a(seed + ":" + participant), Fisher-Yates;
 *     the same code is in analysis/experiment/order.py (and the PsychoPy script).
 */
(function (root) {
  'use strict';

  // ---------------------------------------------------------------- pure functions
  // These run in node too (module.exports below) so tests compare them with Python.

  function utf8(text) {
    return new TextEncoder().encode(String(text));
  }

  /** FNV-1a, 32 bit, over the UTF-8 bytes of text (same as order.fnv1a32). */
  function fnv1a32(text) {
    var bytes = utf8(text);
    var h = 0x811c9dc5;
    for (var i = 0; i < bytes.length; i++) {
      h ^= bytes[i];
      h = Math.imul(h, 0x01000193) >>> 0;
    }
    return h >>> 0;
  }

  /** mulberry32: floats u / 2^32 in [0, 1) (same as order.mulberry32). */
  function mulberry32(seed) {
    var a = seed >>> 0;
    return function () {
      a = (a + 0x6d2b79f5) | 0;
      var t = Math.imul(a ^ (a >>> 15), 1 | a);
      t = (t + Math.imul(t ^ (t >>> 7), 61 | t)) ^ t;
      return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
    };
  }

  /** Fisher-Yates shuffle of a copy (same draws as order.shuffle). */
  function shuffle(items, rng) {
    var out = items.slice();
    for (var i = out.length - 1; i > 0; i--) {
      var j = Math.floor(rng() * (i + 1));
      var tmp = out[i]; out[i] = out[j]; out[j] = tmp;
    }
    return out;
  }

  /** Presentation order of ids for a participant (same as order.trial_order). */
  function trialOrder(participant, ids, conditions, order, seed) {
    if (order === 'fixed') return ids.slice();
    var rng = mulberry32(fnv1a32(String(seed || '') + ':' + participant));
    if (order === 'random') return shuffle(ids, rng);
    var blocks = [];
    conditions.forEach(function (c) { if (blocks.indexOf(c) < 0) blocks.push(c); });
    var out = [];
    shuffle(blocks, rng).forEach(function (b) {
      out = out.concat(shuffle(ids.filter(function (_, k) { return conditions[k] === b; }), rng));
    });
    return out;
  }

  /** List 1..n of a participant without ?list= (same as order.participant_list). */
  function participantList(participant, nLists, seed) {
    return (fnv1a32('list:' + String(seed || '') + ':' + participant) % nLists) + 1;
  }

  /** Pointer position -> image pixels (pixel centres at integers, y down). */
  function toImagePx(clientX, clientY, rect, naturalWidth, naturalHeight) {
    return {
      x: (clientX - rect.left) * naturalWidth / rect.width - 0.5,
      y: (clientY - rect.top) * naturalHeight / rect.height - 0.5
    };
  }

  /** The participant id from URL parameters (get(name) -> value or null): the named one, then the defaults. */
  function participantId(get, param) {
    return String(get(param || 'participant') || get('participant') || get('PROLIFIC_PID') || '').trim();
  }

  /** A completion URL with {participant} replaced by the (URL-encoded) id. */
  function completionHref(url, participant) {
    return String(url).replace(/\{participant\}/g, encodeURIComponent(participant));
  }

  /** Participant ids the page accepts (the same rule as options.PARTICIPANT_ID). */
  var PARTICIPANT_ID = /^[A-Za-z0-9][A-Za-z0-9_.@-]{0,63}$/;
  var PLAIN_NUMBER = /^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$/;

  /** A text a spreadsheet would run as a formula, with a ' before it (numbers as they are). */
  function neutralise(value) {
    if (typeof value !== 'string' || !/^[=+\-@\t\r]/.test(value) || PLAIN_NUMBER.test(value)) return value;
    return "'" + value;
  }

  /** One CSV field (RFC 4180): quoted when it holds a comma, quote, line break or edge space. */
  function csvField(value) {
    var s = value === null || value === undefined ? '' : String(neutralise(value));
    if (/[",\r\n]/.test(s) || /^\s|\s$/.test(s)) return '"' + s.replace(/"/g, '""') + '"';
    return s;
  }

  function toCSV(rows, columns) {
    var lines = [columns.map(csvField).join(',')];
    rows.forEach(function (r) {
      lines.push(columns.map(function (c) { return csvField(r[c]); }).join(','));
    });
    return lines.join('\n') + '\n';
  }

  var COLUMNS = ['participant', 'stimulus_id', 'x', 'y', 'click', 'trial', 'rt_ms', 'condition', 'list',
    'parent_id', 'shown_w', 'shown_h', 'px_per_deg', 'px_per_mm', 'viewing_distance_cm', 'screen_w',
    'screen_h', 'device_pixel_ratio', 'pointer_type', 'user_agent', 'timestamp'];
  var ID_RULE = 'A participant id is 1 to 64 letters, digits, _ . @ or -, beginning with a letter or digit.';
  var CARD_WIDTH_MM = 85.60;  // ISO/IEC 7810 ID-1 (credit card)

  /** CSS px per degree: the central degree as a linear scale (PsychoPy 'deg'; calibration.py). */
  function pxPerDegree(pxPerMm, distanceMm) {
    return pxPerMm * 2 * distanceMm * Math.tan(0.5 * Math.PI / 180);
  }

  var api = {
    fnv1a32: fnv1a32, mulberry32: mulberry32, shuffle: shuffle, trialOrder: trialOrder,
    participantList: participantList, toImagePx: toImagePx, toCSV: toCSV, csvField: csvField,
    pxPerDegree: pxPerDegree, COLUMNS: COLUMNS, PARTICIPANT_ID: PARTICIPANT_ID, neutralise: neutralise,
    participantId: participantId, completionHref: completionHref, ID_RULE: ID_RULE
  };
  if (typeof module === 'object' && module.exports) {
    module.exports = api;
    return;
  }
  root.attneave = api;
  // the jsPsych page takes the functions above and runs its own timeline, not this page
  if (root.attneaveLibraryOnly) return;

  // ---------------------------------------------------------------- the page

  var doc = root.document;
  var $ = function (id) { return doc.getElementById(id); };
  var cfg = JSON.parse($('attneave-config').textContent);
  var params = new URLSearchParams(root.location.search);
  var screenEl = $('screen'), stage = $('stage'), frame = $('frame'), img = $('stimulus');
  var marks = $('marks'), fixation = $('fixation'), nextBtn = $('next'), undoBtn = $('undo');
  var progress = $('progress'), prompt = $('prompt');

  var session = {
    participant: null, list: null, pxPerMm: null, pxPerDeg: null,
    distanceCm: cfg.viewing_distance_cm, order: [], extra: {}
  };
  var completion = cfg.completion_url || null;  // JATOS's JSON input may replace it
  var recorded = cfg.record_params || [];
  var data = root.attneaveData = [];
  var practiceData = root.attneavePractice = [];
  root.attneave.session = session;
  root.attneave.config = cfg;

  // #next runs the current screen's action; one handler, so hosts and tests need one element
  var onNext = null;
  nextBtn.addEventListener('click', function () {
    // a focused button would also take the space bar's own click: keep focus off it
    nextBtn.blur();
    if (nextBtn.disabled || !onNext) return;
    var f = onNext;
    onNext = null;
    nextBtn.disabled = true;
    f();
  });
  function waitNext(action, enabled) {
    onNext = action;
    nextBtn.hidden = false;
    nextBtn.disabled = enabled === false;
  }

  doc.addEventListener('keydown', function (e) {
    var typing = e.target && (e.target.tagName === 'INPUT' || e.target.tagName === 'TEXTAREA');
    if ((e.key === ' ' || e.code === 'Space') && !typing) {
      e.preventDefault();  // no page scroll
      if (!e.repeat) nextBtn.click();  // a held space bar advances once
    } else if (e.key === 'Enter' && typing) {
      e.preventDefault();
      nextBtn.click();
    } else if ((e.key === 'Backspace' || e.key === 'z' || e.key === 'Z') && !typing && trial) {
      e.preventDefault();  // Backspace must not navigate back
      undo();
    }
  });

  function el(tag, attrs, children) {
    var node = doc.createElement(tag);
    Object.keys(attrs || {}).forEach(function (k) {
      if (k === 'text') node.textContent = attrs[k]; else node.setAttribute(k, attrs[k]);
    });
    (children || []).forEach(function (c) { node.appendChild(c); });
    return node;
  }
  function paragraphs(text) {
    return String(text).split(/\n\s*\n/).map(function (p) { return el('p', { text: p.trim() }); });
  }
  function showScreen(nodes, label) {
    stage.hidden = true;
    screenEl.hidden = false;
    screenEl.innerHTML = '';
    screenEl.setAttribute('data-screen', label);
    var panel = el('div', { 'class': 'panel' }, nodes);
    screenEl.appendChild(panel);
    undoBtn.hidden = true;
    prompt.textContent = '';
  }
  function hideScreen() {
    screenEl.hidden = true;
    screenEl.removeAttribute('data-screen');  // data-screen names the screen shown, and only that
  }
  var halted = false;  // an error screen is final: no timer still pending may show a trial over it
  function fail(message) {
    halted = true;
    underway = false;
    trial = null;
    img.removeAttribute('data-stimulus-id');  // no stimulus is shown any more
    showScreen([el('p', { 'class': 'error', text: message })], 'error');
    nextBtn.hidden = true;
    onNext = null;
  }
  function positiveParam(name) {
    if (!params.has(name)) return null;
    var v = Number(params.get(name));
    if (!(isFinite(v) && v > 0)) throw new Error('URL parameter ' + name + ' must be a positive number, got ' + params.get(name));
    return v;
  }

  // ---------------------------------------------------------------- screens

  function askParticipant(done) {
    var input = el('input', { type: 'text', id: 'participant-input', autocomplete: 'off', 'aria-label': 'participant id' });
    var why = el('p', { id: 'participant-error', 'class': 'error', text: '' });
    showScreen([el('h1', { text: cfg.title }), el('p', { text: 'Please enter your participant ID.' }), input, why],
      'participant');
    waitNext(function () { done(input.value.trim()); }, false);
    input.addEventListener('input', function () {
      var v = input.value.trim();
      why.textContent = v === '' || PARTICIPANT_ID.test(v) ? '' : ID_RULE;
      nextBtn.disabled = !PARTICIPANT_ID.test(v);
    });
    input.focus();
  }

  function calibrate(done) {
    // Li et al. (2020) virtual chinrest, first step: match an on-screen card to a real one
    var width = Math.min(323.5, (root.innerWidth || 400) - 60);  // 323.5 CSS px = 85.6 mm at 96 dpi
    var card = el('div', { 'class': 'card', id: 'card' });
    var range = el('input', { type: 'range', id: 'card-size', min: '100', max: '1200', step: '0.5', value: String(width), 'aria-label': 'card size' });
    var minus = el('button', { type: 'button', id: 'card-smaller', text: '−' });
    var plus = el('button', { type: 'button', id: 'card-larger', text: '+' });
    function set(w) {
      width = Math.max(60, Math.min(2000, w));
      card.style.width = width + 'px';
      range.value = String(width);
    }
    range.addEventListener('input', function () { set(Number(range.value)); });
    minus.addEventListener('click', function () { set(width - 1); });
    plus.addEventListener('click', function () { set(width + 1); });
    set(width);
    showScreen([
      el('h1', { text: 'Screen size' }),
      el('p', { text: 'Hold a credit card (or any card of that size: bank card, ID card) flat against the screen, over the picture below. Use the slider or the − and + buttons until the picture is exactly as wide as the card.' }),
      el('div', { 'class': 'card-area' }, [card]),
      el('div', { 'class': 'card-controls' }, [minus, range, plus]),
      el('p', { text: 'Then sit about ' + Math.round(session.distanceCm) + ' cm (an arm\'s length) from the screen and keep that distance.' })
    ], 'calibration');
    waitNext(function () { done(card.getBoundingClientRect().width / CARD_WIDTH_MM); });
  }

  function instructions(done) {
    showScreen([el('h1', { text: cfg.title })].concat(paragraphs(cfg.instructions)), 'instructions');
    waitNext(done);
  }

  function message(text, label, done) {
    if (halted) return;
    showScreen(paragraphs(text), label);
    waitNext(done);
  }

  // ---------------------------------------------------------------- progress kept in the browser

  // A reload, a closed tab or a crashed browser must not cost a participant the trials done:
  // the rows are kept after every trial under this page's settings and the participant's id
  // (a page built with other settings never resumes another's progress).
  var storeKey = null;
  var underway = false;  // trials begun and not finished: leaving the page asks first
  var savedDone = 0;     // the trials this tab last kept (or resumed from)
  function saveProgress(done, finished) {
    // The same participant open in two tabs (a link opened twice) would show stimuli twice and each
    // tab would keep its own trials over the other's: the tab that keeps a trial first goes on, the
    // other stops (its view of the kept progress is out of date).
    var kept = savedProgress();
    if (kept && kept.done !== savedDone) { openElsewhere(); return; }
    try {
      root.localStorage.setItem(storeKey, JSON.stringify({
        version: 1, list: session.list, order: session.order, done: done, finished: finished,
        pxPerMm: session.pxPerMm, pxPerDeg: session.pxPerDeg, distanceCm: session.distanceCm, rows: data
      }));
      savedDone = done;
    } catch (err) { /* storage full or disabled (private mode): the page still works, without resuming */ }
  }
  function savedProgress() {
    try {
      var s = JSON.parse(root.localStorage.getItem(storeKey) || 'null');
      var same = s && s.version === 1 && s.list === session.list && Array.isArray(s.rows)
        && JSON.stringify(s.order) === JSON.stringify(session.order) && s.done >= 1 && s.done <= s.order.length;
      return same ? s : null;
    } catch (err) { return null; }
  }
  function openElsewhere() {
    fail('This experiment is open in another tab or window, and goes on there. Please close this one.');
  }
  // another tab of this page changed this participant's progress: it is running them, so this one stops
  root.addEventListener('storage', function (e) {
    if (underway && !halted && storeKey !== null && e.key === storeKey) openElsewhere();
  });
  function forgetProgress() {
    try { root.localStorage.removeItem(storeKey); } catch (err) { /* nothing kept */ }
  }
  root.addEventListener('beforeunload', function (e) {
    if (!underway) return;
    e.preventDefault();
    e.returnValue = '';  // the browser's own "leave site?" question
  });

  // ---------------------------------------------------------------- trials

  var trial = null;  // the running trial: {stim, clicks, onset, ...}
  var preloaded = {};
  function preload(stims) {
    stims.forEach(function (s) {
      if (!preloaded[s.src]) { var im = new Image(); im.src = s.src; preloaded[s.src] = im; }
    });
  }

  /** CSS px per image px: the largest image's larger side is size_deg degrees (or size_px px). */
  function cssScale() {
    var size = cfg.scale.size_px !== null ? cfg.scale.size_px : cfg.scale.size_deg * session.pxPerDeg;
    return size / cfg.scale.max_side;
  }

  /** Size the stimulus: its size in degrees (or px), shrunk to fit the stage if larger (shown_w/shown_h). */
  function fit(stim) {
    var scale = cssScale();
    var w = stim.width * scale, h = stim.height * scale;
    var room = Math.min((stage.clientWidth - 8) / w, (stage.clientHeight - 8) / h, 1);
    img.style.width = (w * room) + 'px';
    img.style.height = (h * room) + 'px';
  }
  // A window resized or a phone turned mid-trial: fit the stimulus again, or part of it would be cut
  // off out of reach. Clicks are mapped with the image's rect at the moment of the click and the
  // marks sit in % of the image, so both stay on the points chosen.
  function refit() { if (trial && !frame.hidden) fit(trial.stim); }
  root.addEventListener('resize', refit);
  if (root.ResizeObserver) new root.ResizeObserver(refit).observe(stage);

  function needClicks() { return cfg.min_clicks; }
  function maxClicks() { return cfg.max_clicks === null ? Infinity : cfg.max_clicks; }

  function updateControls() {
    var n = trial.clicks.length;
    nextBtn.disabled = n < needClicks();
    undoBtn.disabled = n === 0;
    if (cfg.clicks === 'done') {
      prompt.textContent = n < needClicks()
        ? 'Click at least ' + needClicks() + ' point' + (needClicks() > 1 ? 's' : '') + ' (' + n + ' so far)'
        : n + ' point' + (n > 1 ? 's' : '') + ' — press Next when done';
    } else {
      prompt.textContent = n < cfg.clicks ? 'Click ' + (cfg.clicks - n) + ' more point' + (cfg.clicks - n > 1 ? 's' : '') : 'Press Next';
    }
  }

  function runTrial(stim, label, done) {
    if (halted) return;
    hideScreen();
    stage.hidden = false;
    frame.hidden = true;
    undoBtn.hidden = true;
    prompt.textContent = '';
    progress.textContent = label;
    nextBtn.disabled = true;
    onNext = null;
    function show() {
      if (halted) return;
      fixation.hidden = true;
      img.onload = null;
      img.setAttribute('data-stimulus-id', stim.id);
      marks.innerHTML = '';
      undoBtn.hidden = !cfg.undo;
      var t = trial = { stim: stim, clicks: [], onset: null };
      waitNext(function () {
        trial = null;
        frame.hidden = true;
        img.removeAttribute('data-stimulus-id');  // present only while a stimulus is shown
        done(t);
      });
      updateControls();  // #next stays disabled until the clicks are in
      // sized once the controls below hold their final text (on a phone the prompt takes a line)
      fit(stim);
      frame.hidden = false;
      // onset = the first frame on which the image is painted
      root.requestAnimationFrame(function () { t.onset = root.performance.now(); });
    }
    function load() {
      img.onload = null;
      img.onerror = function () { fail('Could not load image ' + stim.src + '.'); };
      var ready = function () {
        var fix = Number(cfg.fixation_ms) || 0;
        if (fix > 0) { fixation.hidden = false; root.setTimeout(show, fix); } else show();
      };
      img.removeAttribute('data-stimulus-id');
      if (img.getAttribute('src') === stim.src && img.complete) { ready(); return; }
      img.onload = ready;
      img.src = stim.src;
    }
    load();
  }

  img.addEventListener('pointerdown', function (e) {
    if (!trial || !e.isPrimary || frame.hidden) return;
    // only the main button (or a touch / pen contact) selects a point: a right-click opens a menu,
    // a middle-click scrolls; neither is a choice
    if (e.button !== 0) return;
    e.preventDefault();  // no image drag, no text selection, no emulated mouse events
    if (trial.clicks.length >= maxClicks()) return;
    var now = root.performance.now();
    var rect = img.getBoundingClientRect();
    var p = toImagePx(e.clientX, e.clientY, rect, img.naturalWidth || trial.stim.width, img.naturalHeight || trial.stim.height);
    trial.clicks.push({
      x: p.x, y: p.y, rt: trial.onset === null ? 0 : now - trial.onset, pointer: e.pointerType || 'mouse',
      shown_w: rect.width, shown_h: rect.height, time: new Date().toISOString()
    });
    var m = el('div', { 'class': 'mark' });
    m.style.left = (100 * (e.clientX - rect.left) / rect.width) + '%';  // in % of the image: stays put
    m.style.top = (100 * (e.clientY - rect.top) / rect.height) + '%';   // when the image is resized
    marks.appendChild(m);
    updateControls();
  });

  // no context menu on the stimulus (right-click, a long press on Android): it hides the shape
  img.addEventListener('contextmenu', function (e) { e.preventDefault(); });

  function undo() {
    if (!trial || !trial.clicks.length || !cfg.undo) return;
    trial.clicks.pop();
    if (marks.lastChild) marks.removeChild(marks.lastChild);
    updateControls();
  }
  undoBtn.addEventListener('click', function () { undoBtn.blur(); undo(); });

  function round(v, digits) {
    var f = Math.pow(10, digits);
    return Math.round(v * f) / f;
  }

  function rowsOf(t, trialNumber) {
    var scr = root.screen || {};
    return t.clicks.map(function (c, k) {
      var row = {
        participant: session.participant, stimulus_id: t.stim.id, x: round(c.x, 3), y: round(c.y, 3),
        click: k + 1, trial: trialNumber, rt_ms: Math.round(c.rt), condition: t.stim.condition,
        list: session.list, parent_id: t.stim.parent_id, shown_w: round(c.shown_w, 3), shown_h: round(c.shown_h, 3),
        px_per_deg: session.pxPerDeg === null ? '' : round(session.pxPerDeg, 4),
        px_per_mm: session.pxPerMm === null ? '' : round(session.pxPerMm, 4),
        viewing_distance_cm: session.distanceCm, screen_w: scr.width, screen_h: scr.height,
        device_pixel_ratio: root.devicePixelRatio || 1, pointer_type: c.pointer,
        user_agent: root.navigator.userAgent, timestamp: c.time
      };
      recorded.forEach(function (k) { row[k] = session.extra[k]; });
      return row;
    });
  }

  function pause(ms, then) {
    if (halted) return;
    if (!(ms > 0)) { then(); return; }
    stage.hidden = false;
    hideScreen();
    frame.hidden = true;
    fixation.hidden = true;
    undoBtn.hidden = true;
    prompt.textContent = '';
    root.setTimeout(then, ms);
  }

  function runSequence(stims, isPractice, done, from) {
    var i = from || 0;
    function step() {
      if (i >= stims.length) { done(); return; }
      var stim = stims[i];
      var label = (isPractice ? 'Practice ' : 'Trial ') + (i + 1) + ' of ' + stims.length;
      runTrial(stim, label, function (t) {
        i += 1;
        var rows = rowsOf(t, isPractice ? 'practice' : i);
        Array.prototype.push.apply(isPractice ? practiceData : data, rows);
        if (!isPractice) saveProgress(i, false);
        pause(cfg.iti_ms, function () {
          var brk = !isPractice && cfg.break_every > 0 && i % cfg.break_every === 0 && i < stims.length;
          if (brk) {
            message('Take a short break. ' + i + ' of ' + stims.length + ' shapes done. Press Next to go on.', 'break', step);
          } else step();
        });
      });
    }
    step();
  }

  // ---------------------------------------------------------------- the end

  function csv() { return toCSV(data, COLUMNS.concat(recorded)); }

  function complete() { root.location.assign(completionHref(completion, session.participant)); }
  function completionLink() {
    return el('a', { id: 'complete', href: completionHref(completion, session.participant), text: 'Continue to finish the study' });
  }

  /** The data are with the experimenter: none stays in this browser, only a note that the participant is done. */
  function markSubmitted() {
    try {
      root.localStorage.setItem(storeKey, JSON.stringify({
        version: 1, list: session.list, order: session.order, done: session.order.length, finished: true,
        submitted: true, rows: []
      }));
    } catch (err) { forgetProgress(); }
  }

  /** JATOS: the CSV as the component's result data, then the end of the study (and the completion URL). */
  function submitJatos(status, text, link) {
    var attempt = 0;
    var delays = [1000, 2000, 4000];
    status.setAttribute('data-state', 'pending');
    status.textContent = 'Sending your data…';
    function tryOnce() {
      attempt += 1;
      Promise.resolve().then(function () { return root.jatos.submitResultData(text); }).then(function () {
        markSubmitted();
        status.setAttribute('data-state', 'ok');
        status.textContent = 'Your data were sent. Thank you.';
        if (completion) root.jatos.endStudyAndRedirect(completionHref(completion, session.participant));
        else root.jatos.endStudy();
      }, function (err) {
        if (attempt <= delays.length) { root.setTimeout(tryOnce, delays[attempt - 1]); return; }
        status.setAttribute('data-state', 'failed');
        status.textContent = 'Your data could not be sent (' + ((err && err.message) || err) + '). Please download the file with the link below and send it to the experimenter.';
        status.parentNode.appendChild(el('p', {}, [link]));
      });
    }
    tryOnce();
  }

  function submit(status) {
    var body = JSON.stringify({ participant: session.participant, rows: data, csv: csv() });
    var attempt = 0;
    var delays = [1000, 2000, 4000];  // backoff between the 4 attempts
    status.setAttribute('data-state', 'pending');
    status.textContent = 'Sending your data…';
    function tryOnce() {
      attempt += 1;
      root.fetch(cfg.submit_url, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: body })
        .then(function (r) { if (!r.ok) throw new Error('HTTP ' + r.status); ok(); })
        .catch(function (err) {
          if (attempt <= delays.length) root.setTimeout(tryOnce, delays[attempt - 1]);
          else {
            status.setAttribute('data-state', 'failed');
            status.textContent = 'Your data could not be sent (' + err.message + '). Please download the file with the link above and send it to the experimenter.';
            if (completion) status.parentNode.appendChild(el('p', {}, [completionLink()]));
          }
        });
    }
    function ok() {
      // opening the page again shows the end instead of starting over
      markSubmitted();
      status.setAttribute('data-state', 'ok');
      status.textContent = 'Your data were sent. Thank you.';
      if (completion) complete();  // only now: the data are saved
    }
    tryOnce();
  }

  function finish() {
    if (halted) return;
    underway = false;
    saveProgress(session.order.length, true);
    if (halted) return;
    var text = csv();
    var name = 'attneave_' + String(session.participant).replace(/[^A-Za-z0-9_.-]/g, '_') + '.csv';
    var link = el('a', { id: 'download', href: 'data:text/csv;charset=utf-8,' + encodeURIComponent(text), download: name, text: 'Download your data (' + name + ')' });
    var nodes = paragraphs(cfg.end_text);
    if (!cfg.jatos) nodes.push(el('p', {}, [link]));  // in JATOS only when the submission failed
    var status = null;
    if (cfg.submit_url || cfg.jatos) {
      status = el('p', { id: 'submit-status' });
      nodes.push(status);
    } else if (completion) {
      nodes.push(el('p', {}, [completionLink()]));  // no way to know the file was saved: the participant goes on
    }
    showScreen(nodes, 'end');
    progress.textContent = '';
    nextBtn.hidden = true;  // the last screen: nothing to advance to
    onNext = null;
    if (cfg.jatos) submitJatos(status, text, link);
    else if (status) submit(status);
  }

  // ---------------------------------------------------------------- start

  function start() {
    try {
      session.distanceCm = positiveParam('distance_cm') || cfg.viewing_distance_cm;
      var ppd = positiveParam('px_per_deg'), ppm = positiveParam('px_per_mm');
      if (ppd !== null) session.pxPerDeg = ppd;
      else if (ppm !== null) { session.pxPerMm = ppm; session.pxPerDeg = pxPerDegree(ppm, session.distanceCm * 10); }
      else if (cfg.px_per_deg !== null) session.pxPerDeg = cfg.px_per_deg;
    } catch (err) { fail(err.message); return; }
    var id = participantId(function (k) { return params.get(k); }, cfg.participant_param);
    // the id comes from the address, which anyone can write: it goes into file names, storage keys
    // and the CSV, so only ids of the documented form are taken
    if (id && !PARTICIPANT_ID.test(id)) { fail('This participant id cannot be used. ' + ID_RULE); return; }
    if (id) withParticipant(id); else askParticipant(withParticipant);
  }

  function withParticipant(id) {
    session.participant = id;
    // anyone can write the address: the recorded parameters are kept as text, at most 200 characters
    recorded.forEach(function (k) { session.extra[k] = String(params.get(k) || '').slice(0, 200); });
    var k = cfg.lists;
    if (params.has('list')) {
      var l = Number(params.get('list'));
      if (!(l >= 1 && l <= k && Math.floor(l) === l)) { fail('URL parameter list must be a whole number from 1 to ' + k + ', got ' + params.get('list')); return; }
      session.list = l;
    } else session.list = participantList(id, k, cfg.seed);
    var mine = cfg.stimuli.filter(function (s) { return s.lists.indexOf(session.list) >= 0; });
    var ids = trialOrder(id, mine.map(function (s) { return s.id; }), mine.map(function (s) { return s.condition; }), cfg.order, cfg.seed);
    var byId = {};
    mine.forEach(function (s) { byId[s.id] = s; });
    session.order = ids;
    var trials = ids.map(function (s) { return byId[s]; });
    storeKey = 'attneave:' + fnv1a32(JSON.stringify(cfg)).toString(16) + ':' + id;
    if (params.get('fresh') === '1') {
      forgetProgress();
      // ?fresh=1 forgets once: a reload of the same address (mid-experiment) must resume, not forget again
      try {
        var u = new URL(root.location.href);
        u.searchParams.delete('fresh');
        root.history.replaceState(root.history.state, '', u.href);
      } catch (err) { /* an address that cannot be rewritten: a reload starts again, as before */ }
    }
    var saved = savedProgress();
    if (saved) { resume(saved, trials); return; }
    underway = true;
    preload(cfg.practice.concat(trials));
    var needsScale = cfg.scale.size_px === null && session.pxPerDeg === null;
    var go = function () {
      instructions(function () {
        if (cfg.practice.length) {
          runSequence(cfg.practice, true, function () {
            message('The practice is over. The experiment starts now.', 'practice-end', function () { runSequence(trials, false, finish); });
          });
        } else runSequence(trials, false, finish);
      });
    };
    if (needsScale) {
      calibrate(function (pxPerMm) {
        session.pxPerMm = pxPerMm;
        session.pxPerDeg = pxPerDegree(pxPerMm, session.distanceCm * 10);
        go();
      });
    } else go();
  }

  /** A participant whose data were sent opens the page again: the end screen, without the data. */
  function sentAlready() {
    underway = false;
    var status = el('p', { id: 'submit-status', 'data-state': 'ok', text: 'Your data were sent. Thank you.' });
    showScreen(paragraphs(cfg.end_text).concat([status]), 'end');
    progress.textContent = '';
    nextBtn.hidden = true;
    onNext = null;
  }

  /** Go on from saved progress: its rows and calibration back, practice and instructions skipped. */
  function resume(saved, trials) {
    Array.prototype.push.apply(data, saved.rows);
    session.pxPerMm = saved.pxPerMm;
    session.pxPerDeg = saved.pxPerDeg;
    session.distanceCm = saved.distanceCm;
    savedDone = saved.done;
    if (saved.submitted) { sentAlready(); return; }
    if (saved.finished || saved.done >= trials.length) { finish(); return; }
    underway = true;
    preload(trials.slice(saved.done));
    message('Welcome back. You had done ' + saved.done + ' of ' + trials.length + ' shapes; the experiment goes on '
      + 'with the next one. Press Next to go on.', 'resume', function () { runSequence(trials, false, finish, saved.done); });
  }

  /** JATOS: the study link's parameters (Prolific's, say) and the JSON input, once jatos.js is ready. */
  function adoptJatos() {
    var q = root.jatos.urlQueryParameters || {};
    Object.keys(q).forEach(function (k) { if (!params.has(k)) params.set(k, String(q[k])); });
    var input = Object.assign({}, root.jatos.studyJsonInput || {}, root.jatos.componentJsonInput || {});
    if (typeof input.completion_url === 'string' && /^(https?:\/\/|\/)/.test(input.completion_url)) completion = input.completion_url;
  }

  if (!cfg.jatos) start();
  else if (!root.jatos || typeof root.jatos.onLoad !== 'function') {
    fail('This page runs in JATOS: jatos.js, which JATOS serves beside it, could not be loaded.');
  } else root.jatos.onLoad(function () { adoptJatos(); start(); });
})(typeof window !== 'undefined' ? window : this);
