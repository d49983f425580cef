/*
 * The attneave task as a jsPsych 8 timeline (written by `attneave experiment --jspsych`).
 *
 *   attneaveJsPsych.timeline(jsPsych)  the task's trials, to put in your timeline as they are:
 *       [participant id screen (when the URL has none)], [card calibration (when the scale is not
 *       fixed)], instructions, practice (trial_type attneave-points-practice), the practice's end,
 *       then the participant's list of stimuli in the seeded order (attneave-points; a break screen
 *       every break_every trials). The same settings, order, lists and calibration as index.html
 *       (the functions come from task.js, which runs no page here).
 *   attneaveJsPsych.finish(jsPsych)   for initJsPsych's on_finish: the end screen, and the data
 *       (jsPsych.data.get(): every trial of the timeline, yours too) saved: with JATOS submitted as
 *       JSON through jatos.submitResultData, else POSTed to submit_url as {participant, rows, csv},
 *       else offered as the CSV #download; then the completion URL, once saved.
 *
 * Every row gets the properties participant, list and the recorded URL parameters (Prolific's
 * STUDY_ID and SESSION_ID, MTurk's assignmentId and hitId) through jsPsych.data.addProperties.
 */
var attneaveJsPsych = (function (root) {
  'use strict';
  var A = root.attneave;
  var state = {
    cfg: null, params: null, participant: null, list: null, order: [], extra: {},
    pxPerMm: null, pxPerDeg: null, distanceCm: null, done: 0, completion: null, error: null
  };

  function readConfig() {
    return JSON.parse(root.document.getElementById('attneave-config').textContent);
  }

  /** URL parameters; in JATOS the study link's own (jatos.urlQueryParameters) too. */
  function urlParams() {
    var params = new URLSearchParams(root.location.search);
    var q = (root.jatos && root.jatos.urlQueryParameters) || {};
    Object.keys(q).forEach(function (k) { if (!params.has(k)) params.set(k, String(q[k])); });
    return params;
  }

  function positive(params, name) {
    if (!params.has(name)) return null;
    var v = Number(params.get(name));
    if (!(isFinite(v) && v > 0)) throw new Error('URL parameter ' + name + ' must be a positive number, got ' + params.get(name));
    return v;
  }

  /** The participant's list and trial order (the standalone page's rule), and the rows' properties. */
  function setParticipant(jsPsych, id) {
    var cfg = state.cfg, params = state.params;
    state.participant = id;
    if (params.has('list')) {
      var l = Number(params.get('list'));
      if (!(l >= 1 && l <= cfg.lists && Math.floor(l) === l)) throw new Error('URL parameter list must be a whole number from 1 to ' + cfg.lists + ', got ' + params.get('list'));
      state.list = l;
    } else state.list = A.participantList(id, cfg.lists, cfg.seed);
    var mine = cfg.stimuli.filter(function (s) { return s.lists.indexOf(state.list) >= 0; });
    state.order = A.trialOrder(id, mine.map(function (s) { return s.id; }), mine.map(function (s) { return s.condition; }), cfg.order, cfg.seed);
    var props = { participant: id, list: state.list };
    (cfg.record_params || []).forEach(function (k) { props[k] = state.extra[k] = String(params.get(k) || '').slice(0, 200); });
    jsPsych.data.addProperties(props);
  }

  function cssWidth(s) {
    var cfg = state.cfg;
    var size = cfg.scale.size_px !== null ? cfg.scale.size_px : cfg.scale.size_deg * state.pxPerDeg;
    return s.width * size / cfg.scale.max_side;
  }

  function screen(Screen, name, title, text, when) {
    var trial = { type: Screen, screen: name, title: title || '', text: text || '' };
    return when ? { timeline: [trial], conditional_function: when } : trial;
  }

  function pointsTrial(jsPsych, type, practice) {
    var cfg = state.cfg;
    function s() { return jsPsych.evaluateTimelineVariable('s'); }
    return {
      type: type,
      stimulus: function () { return s().src; },
      stimulus_id: function () { return s().id; },
      image_width: function () { return s().width; },
      image_height: function () { return s().height; },
      css_width: function () { return cssWidth(s()); },
      min_clicks: cfg.min_clicks,
      max_clicks: cfg.max_clicks,
      undo: cfg.undo,
      fixation_ms: cfg.fixation_ms,
      post_trial_gap: cfg.iti_ms,
      progress: function () {
        return practice ? 'Practice ' + (cfg.practice.indexOf(s()) + 1) + ' of ' + cfg.practice.length
          : 'Trial ' + (state.done + 1) + ' of ' + state.order.length;
      },
      participant: function () { return state.participant; },
      trial: function () { return practice ? null : state.done + 1; },
      condition: function () { return s().condition; },
      parent_id: function () { return s().parent_id; },
      list: function () { return state.list; },
      px_per_deg: function () { return state.pxPerDeg; },
      px_per_mm: function () { return state.pxPerMm; },
      viewing_distance_cm: function () { return state.distanceCm; },
      on_finish: function () { if (!practice) state.done += 1; }
    };
  }

  /** The task's timeline nodes (see the top of this file). */
  function timeline(jsPsych, cfg) {
    var Screen = root.jsPsychAttneaveScreen;
    cfg = state.cfg = cfg || readConfig();
    state.params = urlParams();
    state.completion = cfg.completion_url || null;
    if (root.jatos) {
      var input = Object.assign({}, root.jatos.studyJsonInput || {}, root.jatos.componentJsonInput || {});
      if (typeof input.completion_url === 'string' && /^(https?:\/\/|\/)/.test(input.completion_url)) state.completion = input.completion_url;
    }
    try {
      state.distanceCm = positive(state.params, 'distance_cm') || cfg.viewing_distance_cm;
      var ppd = positive(state.params, 'px_per_deg'), ppm = positive(state.params, 'px_per_mm');
      if (ppd !== null) state.pxPerDeg = ppd;
      else if (ppm !== null) { state.pxPerMm = ppm; state.pxPerDeg = A.pxPerDegree(ppm, state.distanceCm * 10); }
      else if (cfg.px_per_deg !== null) state.pxPerDeg = cfg.px_per_deg;
      var id = A.participantId(function (k) { return state.params.get(k); }, cfg.participant_param);
      // the id comes from the address, which anyone can write: only ids of the documented form
      if (id && !A.PARTICIPANT_ID.test(id)) throw new Error('This participant id cannot be used. ' + A.ID_RULE);
      if (id) setParticipant(jsPsych, id);
    } catch (err) {
      return [screen(Screen, 'error', '', err.message)];
    }
    (cfg.practice.concat(cfg.stimuli)).forEach(function (s) { new root.Image().src = s.src; });  // preload
    var nodes = [];
    nodes.push({
      timeline: [{
        type: Screen, screen: 'participant', title: cfg.title, text: 'Please enter your participant ID.',
        on_finish: function (d) { setParticipant(jsPsych, d.participant_input); }
      }],
      conditional_function: function () { return state.participant === null; }
    });
    nodes.push({
      timeline: [{
        type: Screen, screen: 'calibration', distance_cm: state.distanceCm,
        on_finish: function (d) {
          state.pxPerMm = d.px_per_mm;
          state.pxPerDeg = A.pxPerDegree(d.px_per_mm, state.distanceCm * 10);
        }
      }],
      conditional_function: function () { return cfg.scale.size_px === null && state.pxPerDeg === null; }
    });
    nodes.push(screen(Screen, 'instructions', cfg.title, cfg.instructions));
    if (cfg.practice.length) {
      nodes.push({ timeline: [pointsTrial(jsPsych, root.jsPsychAttneavePractice, true)],
        timeline_variables: cfg.practice.map(function (s) { return { s: s }; }) });
      nodes.push(screen(Screen, 'practice-end', '', 'The practice is over. The experiment starts now.'));
    }
    var breakScreen = {
      timeline: [{
        type: Screen, screen: 'break',
        text: function () { return 'Take a short break. ' + state.done + ' of ' + state.order.length + ' shapes done. Press Next to go on.'; }
      }],
      conditional_function: function () { return cfg.break_every > 0 && state.done > 0 && state.done % cfg.break_every === 0; }
    };
    nodes.push({
      timeline: [breakScreen, pointsTrial(jsPsych, root.jsPsychAttneavePoints, false)],
      timeline_variables: cfg.stimuli.map(function (s) { return { s: s }; }),
      // the participant's stimuli in the seeded order, known only once the id is (a screen may ask for it)
      sample: { type: 'custom', fn: function () {
        var at = {};
        cfg.stimuli.forEach(function (s, k) { at[s.id] = k; });
        return state.order.map(function (sid) { return at[sid]; });
      } }
    });
    return nodes;
  }

  function el(tag, attrs, children) {
    var node = root.document.createElement(tag);
    Object.keys(attrs || {}).forEach(function (k) {
      if (k === 'text') node.textContent = attrs[k]; else node.setAttribute(k, attrs[k]);
    });
    (children || []).forEach(function (c) { node.appendChild(c); });
    return node;
  }

  function completionHref() { return A.completionHref(state.completion, state.participant); }

  /** The end: the data saved (JATOS, POST or download), then the completion URL. */
  function finish(jsPsych) {
    var cfg = state.cfg;
    var data = jsPsych.data.get();
    var csv = data.csv();
    var name = 'attneave_' + String(state.participant).replace(/[^A-Za-z0-9_.-]/g, '_') + '.csv';
    var link = el('a', { id: 'download', href: 'data:text/csv;charset=utf-8,' + encodeURIComponent(csv), download: name, text: 'Download your data (' + name + ')' });
    var panel = el('div', { 'class': 'panel' }, String(cfg.end_text).split(/\n\s*\n/).map(function (p) { return el('p', { text: p.trim() }); }));
    var status = el('p', { id: 'submit-status' });
    var display = jsPsych.getDisplayElement();
    display.innerHTML = '';
    display.appendChild(el('div', { 'class': 'attneave-app' }, [el('section', { id: 'screen', 'class': 'screen', 'data-screen': 'end' }, [panel])]));
    function failed(why) {
      status.setAttribute('data-state', 'failed');
      status.textContent = 'Your data could not be sent (' + why + '). Please download the file with the link below and send it to the experimenter.';
      panel.appendChild(el('p', {}, [link]));
      if (state.completion) panel.appendChild(el('p', {}, [el('a', { id: 'complete', href: completionHref(), text: 'Continue to finish the study' })]));
    }
    function retry(send, ok) {
      var attempt = 0, delays = [1000, 2000, 4000];
      status.setAttribute('data-state', 'pending');
      status.textContent = 'Sending your data…';
      panel.appendChild(status);
      function once() {
        attempt += 1;
        Promise.resolve().then(send).then(function () {
          status.setAttribute('data-state', 'ok');
          status.textContent = 'Your data were sent. Thank you.';
          ok();
        }, function (err) {
          if (attempt <= delays.length) root.setTimeout(once, delays[attempt - 1]);
          else failed((err && err.message) || String(err));
        });
      }
      once();
    }
    if (cfg.jatos && root.jatos) {
      retry(function () { return root.jatos.submitResultData(data.json()); }, function () {
        if (state.completion) root.jatos.endStudyAndRedirect(completionHref());
        else root.jatos.endStudy();
      });
    } else if (cfg.submit_url) {
      panel.appendChild(el('p', {}, [link]));
      var body = JSON.stringify({ participant: state.participant, rows: data.values(), csv: csv });
      retry(function () {
        return root.fetch(cfg.submit_url, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: body })
          .then(function (r) { if (!r.ok) throw new Error('HTTP ' + r.status); });
      }, function () { if (state.completion) root.location.assign(completionHref()); });
    } else {
      panel.appendChild(el('p', {}, [link]));
      // no way to know the file was saved: the participant goes on by the link
      if (state.completion) panel.appendChild(el('p', {}, [el('a', { id: 'complete', href: completionHref(), text: 'Continue to finish the study' })]));
    }
  }

  return { timeline: timeline, finish: finish, state: state };
})(window);
