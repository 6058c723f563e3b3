// mrbrake studio: the page. Plain JavaScript, no framework, no build step. It holds no numerics:
// every number it shows is a value of the server's JSON (the analysis as `analyze --json` prints
// it), formatted for display; `data-value` keeps the exact value.
'use strict';

const token = new URLSearchParams(location.search).get('token') || '';
const studio = { schema: null, info: null, state: null, revision: 0, inputs: new Map(), sentText: null, study: null };

// --- the API --------------------------------------------------------------------------------
async function api(method, path, body) {
  const options = { method, headers: { 'X-Mrbrake-Token': token } };
  if (body !== undefined) {
    options.headers['Content-Type'] = 'application/json';
    options.body = JSON.stringify(body);
  }
  const response = await fetch(path, options);
  const json = await response.json();
  if (!response.ok) throw new Error(json.error || response.statusText);
  return json;
}

function sessionPath(suffix) {
  return `/api/sessions/${studio.state.id}${suffix || ''}`;
}

async function send(edit) {
  try {
    render(await api('POST', sessionPath('/edit'), edit));
  } catch (e) {
    say(`The edit was not applied: ${e.message}`);
  }
}

function say(text) {
  document.getElementById('status').textContent = text;
}

// --- elements -------------------------------------------------------------------------------
function el(tag, attributes, ...children) {
  const node = document.createElement(tag);
  for (const [k, v] of Object.entries(attributes || {})) {
    if (v === null || v === undefined || v === false) continue;
    node.setAttribute(k, v === true ? '' : String(v));
  }
  for (const child of children) {
    if (child !== null && child !== undefined) node.append(child);
  }
  return node;
}

const SVG_NS = 'http://www.w3.org/2000/svg';
function svgEl(tag, attributes, text) {
  const node = document.createElementNS(SVG_NS, tag);
  for (const [k, v] of Object.entries(attributes || {})) node.setAttribute(k, String(v));
  if (text !== undefined) node.textContent = text;
  return node;
}

// Markup the server rendered (the report's own SVG and tables), shown as is.
function setMarkup(container, markup, empty) {
  if (container.dataset.markup === markup) return;
  container.dataset.markup = markup || '';
  if (markup) {
    container.innerHTML = markup;
  } else {
    container.replaceChildren(el('p', { class: 'empty' }, empty || 'Not solved yet.'));
  }
}

function fmt(value, digits) {
  if (value === null || value === undefined || !Number.isFinite(value)) return '–';
  if (Number.isInteger(value) && Math.abs(value) < 1e6) return String(value);
  const magnitude = Math.abs(value);
  if (magnitude !== 0 && (magnitude < 1e-3 || magnitude >= 1e6)) return value.toExponential(digits - 1);
  return value.toPrecision(digits);
}

// --- the form, from the schema --------------------------------------------------------------
function orderedKeys(node) {
  const keys = [...(node['x-order'] || [])];
  for (const key of Object.keys(node.properties || {})) if (!keys.includes(key)) keys.push(key);
  return keys.filter((k) => node.properties && node.properties[k]);
}

function isTable(node) {
  return node.type === 'object' && node.properties;
}

function choicesOf(node) {
  if (Array.isArray(node.enum)) return node.enum.map((v) => ({ value: v, text: '' }));
  if (Array.isArray(node.oneOf) && node.oneOf.every((b) => 'const' in b)) {
    return node.oneOf.map((b) => ({ value: b.const, text: b.description || '' }));
  }
  return null;
}

function numberBranch(node) {
  if (Array.isArray(node.anyOf)) return node.anyOf.find((b) => b.type === 'number' || b.type === 'integer') || {};
  return node;
}

function rangeText(node) {
  const n = numberBranch(node);
  const unit = node['x-unit'] ? ` ${node['x-unit']}` : '';
  const lo = 'minimum' in n ? `[${n.minimum}` : 'exclusiveMinimum' in n ? `(${n.exclusiveMinimum}` : null;
  const hi = 'maximum' in n ? `${n.maximum}]` : 'exclusiveMaximum' in n ? `${n.exclusiveMaximum})` : null;
  if (lo && hi) return `allowed ${lo}, ${hi}${unit}`;
  if (lo) return `allowed ≥ ${lo.slice(1)}${unit}`;
  return '';
}

function buildForm(schema) {
  const form = document.getElementById('spec-form');
  form.replaceChildren();
  const general = el('fieldset', { 'data-table': '' }, el('legend', {}, 'General'));
  form.append(general);
  for (const key of orderedKeys(schema)) {
    const node = schema.properties[key];
    if (isTable(node)) {
      form.append(buildTable(key, node, (schema.required || []).includes(key)));
    } else {
      general.append(buildField(key, key, node, (schema.required || []).includes(key)));
    }
  }
}

function buildTable(path, node, required) {
  const set = el('fieldset', { 'data-table': path }, el('legend', {}, `[${path}]`));
  if (node.description) set.append(el('p', { class: 'help' }, node.description));
  for (const key of orderedKeys(node)) {
    const child = node.properties[key];
    const childPath = `${path}.${key}`;
    const childRequired = (node.required || []).includes(key);
    set.append(isTable(child) ? buildTable(childPath, child, childRequired) : buildField(childPath, key, child, childRequired));
  }
  return set;
}

function buildField(path, key, node, required) {
  const id = `f-${path.replace(/\./g, '-')}`;
  const unit = node['x-unit'] ? el('span', { class: 'unit' }, ` [${node['x-unit']}]`) : null;
  const label = el('label', { for: id }, key, unit);
  const helpText = [node.description || '', rangeText(node), node.default !== undefined ? `default ${JSON.stringify(node.default)}` : '', required ? '' : 'optional']
    .filter(Boolean).join(' · ');
  const help = el('span', { class: 'help', id: `${id}-help` }, helpText);
  const error = el('span', { class: 'error', id: `${id}-error`, role: 'alert' });
  const choices = choicesOf(node);
  let input;
  if (choices) {
    input = el('select', { id, name: path, 'aria-describedby': `${id}-help ${id}-error` });
    input.append(el('option', { value: '' }, required ? '(choose)' : '(not set)'));
    for (const c of choices) input.append(el('option', { value: c.value, title: c.text || null }, c.value));
  } else {
    const integer = numberBranch(node).type === 'integer' || node.type === 'integer';
    const placeholder = node.anyOf ? ((node.anyOf.find((b) => b.examples) || {}).examples || [''])[0] : '';
    input = el('input', { id, name: path, type: 'text', inputmode: integer ? 'numeric' : null, placeholder, 'aria-describedby': `${id}-help ${id}-error`, autocomplete: 'off' });
    input.dataset.integer = integer ? '1' : '';
  }
  input.dataset.path = path;
  input.addEventListener('change', () => sendField(input));
  studio.inputs.set(path, { input, error });
  return el('div', { class: 'field' }, label, input, help, error);
}

function sendField(input) {
  const text = input.value.trim();
  let value = text === '' ? null : text;
  if (value !== null && /^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$/.test(text)) value = Number(text);
  if (value !== null && input.dataset.integer === '1' && Number.isInteger(Number(text))) value = Number(text);
  send({ path: input.dataset.path, value });
}

// --- rendering the state --------------------------------------------------------------------
function render(state) {
  if (!state || !state.id) return;
  // The long poll and an edit's own answer race: an answer older than the state shown (a POST
  // answered before a solve finished, arriving after the poll's newer state) must not bring
  // the page back in time.
  const shown = studio.state;
  if (shown && shown.id === state.id && state.revision < shown.revision) return;
  studio.state = state;
  studio.revision = Math.max(studio.revision, state.revision);
  const instant = state.instant || {};
  renderForm(instant.values || {}, instant);
  renderToml(state.text);
  renderMessages(instant);
  document.getElementById('design-name').textContent = instant.name || '';
  document.getElementById('undo').disabled = !state.undo;
  document.getElementById('redo').disabled = !state.redo;
  renderStages(state.stages);
  renderFigures(state);
  renderDownloads(state);
  renderCompare(state);
  renderRequests(state);
  const solved = state.stages.filter((s) => s.status === 'done').length;
  document.getElementById('pin').disabled = solved === 0;
}

function renderForm(values, instant) {
  const rules = (studio.schema.allOf || []).find((r) => r.if.properties.configuration.const === values.configuration);
  for (const set of document.querySelectorAll('fieldset[data-table]')) {
    const table = set.dataset.table;
    const forbidden = rules && rules.then.properties && table in rules.then.properties;
    set.hidden = Boolean(forbidden);
  }
  for (const [path, { input, error }] of studio.inputs) {
    if (document.activeElement !== input) {
      const value = values[path];
      input.value = value === undefined ? '' : String(value);
    }
    const problems = (instant.errors || []).filter((e) => e.field === path || (e.field && path.startsWith(`${e.field}.`) && !studio.inputs.has(e.field)));
    const warnings = (instant.warnings || []).filter((w) => w.field === path);
    error.textContent = problems.map((e) => e.message).join('; ');
    error.className = problems.length ? 'error' : 'warning';
    if (!problems.length) error.textContent = warnings.map((w) => `warning: ${w.message}`).join('; ');
    input.setAttribute('aria-invalid', problems.length ? 'true' : 'false');
  }
}

function renderToml(text) {
  const area = document.getElementById('toml');
  if (document.activeElement === area && area.value === studio.sentText) return;
  if (document.activeElement === area && studio.sentText !== null && area.value !== text) return;
  if (area.value !== text) area.value = text;
}

function renderMessages(instant) {
  const box = document.getElementById('errors');
  const lines = [];
  for (const e of instant.errors || []) lines.push(el('p', { class: 'error' }, `error: ${e.text}`));
  for (const w of instant.warnings || []) lines.push(el('p', { class: 'warning' }, w.text));
  if (!lines.length && instant.valid) lines.push(el('p', {}, 'The spec is valid.'));
  box.replaceChildren(...lines);
}

function renderStages(stages) {
  const box = document.getElementById('stages');
  const chips = stages.map((s) => {
    const progress = s.status === 'running' && s.progress[1] ? ` ${s.progress[0]}/${s.progress[1]}` : '';
    const time = s.status === 'done' && s.result.elapsed_s ? ` in ${s.result.elapsed_s.toFixed(2)} s` : '';
    return el('span', { class: `chip ${s.status}`, 'data-stage': s.name, 'data-status': s.status }, `${s.name} mesh: ${s.status}${progress}${time}`);
  });
  const busy = stages.some((s) => s.status === 'running' || s.status === 'queued');
  const stopped = stages.some((s) => s.status === 'cancelled' || s.status === 'failed');
  const cancel = el('button', { type: 'button', id: 'cancel', disabled: !busy }, 'Cancel solve');
  cancel.addEventListener('click', async () => render(await api('POST', sessionPath('/cancel'))));
  const again = el('button', { type: 'button', id: 'resolve', disabled: !stopped }, 'Solve again');
  again.addEventListener('click', async () => render(await api('POST', sessionPath('/solve'))));
  const failures = stages.filter((s) => s.status === 'failed').map((s) => el('p', { class: 'error' }, `${s.name} mesh failed: ${s.result.error}`));
  box.replaceChildren(...chips, cancel, again, ...failures);
  const q = studio.state.queue || {};
  say(busy ? `Solving (solves running: ${q.running}, sessions waiting: ${q.waiting}).` : 'Ready.');
}

// The latest finished stage's result (default over coarse).
function latestResult(state) {
  const done = state.stages.filter((s) => s.status === 'done');
  return done.length ? done[done.length - 1].result : null;
}

const KEY_FIGURES = [
  ['torque at the maximum current', '/torque/at_max_current_Nm', 1, 'N·m', 4],
  ['torque, thesis method', '/torque/thesis_formula_Nm', 1, 'N·m', 4],
  ['mean |B| in the gaps', '/torque/mean_B_T', 1, 'T', 4],
  ['off-state torque', '/torque/off_state_Nm', 1, 'N·m', 3],
  ['dynamic range', '/torque/dynamic_range', 1, '–', 3],
  ['direction 2 torque', '/torque/direction2_at_max_current_Nm', 1, 'N·m', 4],
  ['inductance L (secant)', '/coil/inductance_H', 1e3, 'mH', 4],
  ['time constant L/R', '/coil/time_constant_s', 1e3, 'ms', 3],
];

const INSTANT_FIGURES = [
  ['mass', '/mechanics/mass_kg', 1, 'kg', 4],
  ['rotor inertia', '/mechanics/rotor_inertia_kg_m2', 1e6, 'kg·mm²', 4],
  ['coil resistance at 20 °C', '/coil/resistance_20C_ohm', 1, 'Ω', 4],
  ['current density (4.1)', '/coil/current_density_A_per_mm2', 1, 'A/mm²', 3],
  ['coil power at the maximum current', '/coil/power_W', 1, 'W', 3],
  ['turns', '/coil/turns', 1, '–', 6],
];

function pointer(document, path) {
  return path.split('/').slice(1).reduce((node, key) => (node === null || node === undefined ? undefined : node[key]), document);
}

function figureRow(what, value, scale, unit, digits, from, path) {
  const shown = value === null || value === undefined ? '–' : fmt(value * scale, digits);
  const cell = el('td', { class: 'num', 'data-pointer': path, 'data-value': value === undefined ? '' : JSON.stringify(value), 'data-scale': scale }, shown);
  return el('tr', {}, el('th', { scope: 'row' }, what), cell, el('td', {}, unit), el('td', {}, from));
}

function renderFigures(state) {
  const instant = state.instant || {};
  const result = latestResult(state);
  const body = document.querySelector('#figures tbody');
  const rows = [];
  if (result) {
    for (const [what, path, scale, unit, digits] of KEY_FIGURES) {
      const value = pointer(result.analysis, path);
      if (value === null && path.includes('direction2')) continue;
      rows.push(figureRow(what, value, scale, unit, digits, `${result.stage} mesh`, path));
    }
  }
  if (instant.valid) {
    for (const [what, path, scale, unit, digits] of INSTANT_FIGURES) {
      rows.push(figureRow(what, pointer(instant, path), scale, unit, digits, 'at once', path));
    }
  }
  body.replaceChildren(...rows);
  setMarkup(document.querySelector('#cross-section .svg'), instant.cross_section, 'Fix the spec to see the cross-section.');
  setMarkup(document.querySelector('#parts .table'), instant.parts, '');
  const figures = result ? result.figures : {};
  setMarkup(document.querySelector('#field-map .svg'), figures.field_map, 'Solving…');
  setMarkup(document.querySelector('#torque-current .svg'), figures.torque_current, 'Solving…');
  setMarkup(document.querySelector('#gap-field .svg'), figures.gap_flux_density, 'Solving…');
}

function renderDownloads(state) {
  const solved = state.stages[state.stages.length - 1].status === 'done';
  const link = (id, name, ready) => {
    const a = document.getElementById(id);
    a.href = `${sessionPath(`/download/${name}`)}?token=${token}`;
    a.setAttribute('aria-disabled', ready ? 'false' : 'true');
  };
  link('dl-spec', 'spec.toml', true);
  link('dl-report', 'report.html', solved);
  link('dl-model', 'model.json', solved);
  link('dl-curve', 'curve.csv', solved);
  link('dl-analysis', 'analysis.json', solved);
}

// --- analyses on request: the CLI's JSON of response, thermal and haptic wall -----------------
const REQUESTS = {
  response: {
    title: 'Step and frequency response',
    figures: [['step', 'Torque after a current step'], ['bode', 'Small-signal frequency response']],
    rows: [
      ['−3 dB bandwidth', '/bandwidth_rad_s', 1, 'rad/s', 4],
      ['small-signal gain dT/dI', '/dc_gain_Nm_per_A', 1, 'N·m/A', 4],
      ['t63 after the step up', '/step/0/t63_s', 1e3, 'ms', 3],
      ['t90 after the step up', '/step/0/t90_s', 1e3, 'ms', 3],
      ['t63, direction 2', '/step/1/t63_s', 1e3, 'ms', 3],
    ],
  },
  thermal: {
    title: 'Warm-up and continuous rating',
    figures: [['warmup', 'Coil warm-up']],
    rows: [
      ['continuous current', '/continuous_current_A', 1, 'A', 4],
      ['coil hottest, steady', '/steady/coil_max_T_C', 1, '°C', 4],
      ['time to the insulation limit', '/time_to_limit_s', 1, 's', 4],
      ['largest duty at the maximum current', '/max_duty_at_max_current', 1, '–', 3],
      ['torque, hot coil (current drive)', '/behaviour/torque_hot_current_drive_Nm', 1, 'N·m', 4],
      ['off-state torque, hot', '/behaviour/off_state_torque_hot_Nm', 1, 'N·m', 3],
    ],
  },
  haptic: {
    title: 'Haptic wall with this design',
    figures: [['wall', 'Press and withdraw']],
    rows: [
      ['displayed stiffness', '/displayed_stiffness_Nm_per_rad', 1, 'N·m/rad', 4],
      ['excess torque on withdrawal (peak)', '/withdraw_excess_torque_Nm/peak', 1, 'N·m', 3],
      ['release time', '/release_time_s', 1, 's', 4],
      ['free-motion torque', '/free_motion_torque_Nm', 1, 'N·m', 3],
    ],
  },
};

function renderRequests(state) {
  const requests = state.requests || [];
  const busy = requests.some((r) => r.status === 'queued' || r.status === 'running');
  document.getElementById('analyses-cancel').disabled = !busy;
  for (const button of document.querySelectorAll('[data-analysis]')) {
    const r = requests.find((q) => q.name === button.dataset.analysis);
    button.disabled = !(state.instant && state.instant.valid) || (r && (r.status === 'queued' || r.status === 'running'));
  }
  const box = document.getElementById('analysis-results');
  const shown = requests.filter((r) => r.status !== 'idle');
  box.replaceChildren(...shown.map((r) => requestBlock(r, state.version)));
}

function requestBlock(r, version) {
  const what = REQUESTS[r.name];
  const result = r.result || {};
  const stale = result.version !== undefined && result.version !== version ? ' (of an earlier edit)' : '';
  const time = r.status === 'done' ? ` in ${result.elapsed_s.toFixed(2)} s` : '';
  const chip = el('span', { class: `chip ${r.status}`, 'data-request': r.name, 'data-status': r.status }, `${what.title}: ${r.status}${time}${stale}`);
  const block = el('section', { class: 'request', 'data-request': r.name, 'aria-label': what.title }, chip);
  if (r.status === 'failed') block.append(el('p', { class: 'error' }, `${what.title} failed: ${result.error}`));
  if (r.status !== 'done') return block;
  const rows = what.rows
    .map(([label, path, scale, unit, digits]) => [label, pointer(result.result, path), scale, unit, digits, path])
    .filter(([, value]) => value !== undefined)
    .map(([label, value, scale, unit, digits, path]) => figureRow(label, value, scale, unit, digits, 'on request', path));
  const table = el('table', { class: 'figures' }, el('caption', {}, `${what.title}: key figures (null: not reached or not resolved)`), el('tbody', {}, ...rows));
  const figures = what.figures.map(([key, caption]) => {
    const holder = el('div', { class: 'svg' });
    setMarkup(holder, result.figures[key], '');
    return el('figure', { 'data-figure': key }, el('figcaption', {}, caption), holder);
  });
  const notes = (result.notes || []).map((n) => el('p', { class: 'warning' }, n));
  block.append(table, el('div', { class: 'grid' }, ...figures), ...notes, el('p', { class: 'cli' }, 'The same numbers: ', el('code', {}, result.cli)));
  return block;
}

async function ask(path) {
  try { render(await api('POST', sessionPath(path))); } catch (e) { say(e.message); }
}

// --- compare: pinned designs ----------------------------------------------------------------
function renderCompare(state) {
  const section = document.getElementById('compare');
  const result = latestResult(state);
  const designs = state.pins.map((p, k) => ({ label: `pin ${k + 1}: ${p.analysis.name} (${p.stage})`, analysis: p.analysis, pin: k }));
  if (result) designs.push({ label: `current (${result.stage})`, analysis: result.analysis, pin: null });
  section.hidden = state.pins.length === 0;
  if (section.hidden) return;
  const series = designs.map((d) => ({ label: d.label, points: d.analysis.torque_current_curve.map((p) => [p.current_A, p.torque_Nm]) }));
  document.getElementById('compare-plot').replaceChildren(linePlot(series, 'current [A]', 'torque [N·m]'));
  const table = document.getElementById('compare-table');
  table.tHead.replaceChildren(el('tr', {}, el('th', { scope: 'col' }, 'design'), ...KEY_FIGURES.slice(0, 4).map(([what, , , unit]) => el('th', { scope: 'col' }, `${what} [${unit}]`)), el('th', { scope: 'col' }, '')));
  table.tBodies[0].replaceChildren(...designs.map((d) => {
    const cells = KEY_FIGURES.slice(0, 4).map(([, path, scale, , digits]) => {
      const v = pointer(d.analysis, path);
      return el('td', { class: 'num', 'data-value': JSON.stringify(v) }, fmt(v * scale, digits));
    });
    let action = el('td', {});
    if (d.pin !== null) {
      const remove = el('button', { type: 'button', 'aria-label': `Remove ${d.label}` }, 'Remove');
      remove.addEventListener('click', async () => render(await api('POST', sessionPath('/pin'), { remove: d.pin })));
      action = el('td', {}, remove);
    }
    return el('tr', {}, el('th', { scope: 'row' }, d.label), ...cells, action);
  }));
}

const COLOURS = ['#0072b2', '#d55e00', '#009e73', '#cc79a7', '#56b4e9', '#e69f00', '#000000', '#999999', '#7f3c8d'];

// A small line plot (overlay of pinned designs' curves): axes, ticks, lines, legend.
function linePlot(series, xLabel, yLabel) {
  const W = 640, H = 360, L = 60, R = 16, T = 14, B = 44;
  const all = series.flatMap((s) => s.points);
  const xMax = Math.max(1e-12, ...all.map((p) => p[0]));
  const yMax = Math.max(1e-12, ...all.map((p) => p[1])) * 1.05;
  const x = (v) => L + (v / xMax) * (W - L - R);
  const y = (v) => H - B - (v / yMax) * (H - T - B);
  const svg = svgEl('svg', { viewBox: `0 0 ${W} ${H}`, role: 'img', 'aria-label': `${yLabel} against ${xLabel} of the pinned designs` });
  axes(svg, { W, H, L, R, T, B }, [0, xMax, x, xLabel], [0, yMax, y, yLabel]);
  series.forEach((s, k) => {
    const colour = COLOURS[k % COLOURS.length];
    svg.append(svgEl('polyline', { points: s.points.map((p) => `${x(p[0]).toFixed(1)},${y(p[1]).toFixed(1)}`).join(' '), fill: 'none', stroke: colour, 'stroke-width': 2 }));
    svg.append(svgEl('text', { x: L + 10, y: T + 14 + 15 * k, 'font-size': 11, fill: colour }, s.label));
  });
  return svg;
}

// White ground, the two axes, five ticks each and the axis labels; `xAxis` and `yAxis` are
// [low, high, to pixels, label].
function axes(svg, box, xAxis, yAxis) {
  const { W, H, L, R, T, B } = box;
  const [x0, x1, x, xLabel] = xAxis, [y0, y1, y, yLabel] = yAxis;
  svg.append(svgEl('rect', { x: 0, y: 0, width: W, height: H, fill: '#fff' }));
  svg.append(svgEl('line', { x1: L, y1: H - B, x2: W - R, y2: H - B, stroke: '#333' }));
  svg.append(svgEl('line', { x1: L, y1: T, x2: L, y2: H - B, stroke: '#333' }));
  for (let k = 0; k <= 4; k++) {
    const xv = x0 + ((x1 - x0) * k) / 4, yv = y0 + ((y1 - y0) * k) / 4;
    svg.append(svgEl('text', { x: x(xv), y: H - B + 16, 'text-anchor': 'middle', 'font-size': 11 }, fmt(xv, 3)));
    svg.append(svgEl('text', { x: L - 6, y: y(yv) + 4, 'text-anchor': 'end', 'font-size': 11 }, fmt(yv, 3)));
  }
  svg.append(svgEl('text', { x: (L + W - R) / 2, y: H - 8, 'text-anchor': 'middle', 'font-size': 12 }, xLabel));
  const mid = (T + H - B) / 2;
  svg.append(svgEl('text', { x: 14, y: mid, 'text-anchor': 'middle', 'font-size': 12, transform: `rotate(-90 14 ${mid})` }, yLabel));
}

// --- study: the Pareto plot -----------------------------------------------------------------
function setupStudy(study) {
  studio.study = study;
  document.getElementById('study').hidden = false;
  document.getElementById('study-source').textContent = `${study.store}: ${study.records.length} designs, ${study.front.length} on the front.`;
  const names = study.metrics.map((m) => m.name);
  for (const [id, chosen] of [['study-x', (study.objectives[0] || {}).metric], ['study-y', (study.objectives[1] || study.objectives[0] || {}).metric], ['study-filter', '']]) {
    const select = document.getElementById(id);
    if (id === 'study-filter') select.append(el('option', { value: '' }, '(none)'));
    for (const name of names) select.append(el('option', { value: name, selected: name === chosen }, name));
    select.addEventListener('change', drawStudy);
  }
  for (const id of ['study-min', 'study-max']) document.getElementById(id).addEventListener('change', drawStudy);
  drawStudy();
}

function drawStudy() {
  const study = studio.study;
  const xName = document.getElementById('study-x').value;
  const yName = document.getElementById('study-y').value;
  const filter = document.getElementById('study-filter').value;
  const lo = parseFloat(document.getElementById('study-min').value);
  const hi = parseFloat(document.getElementById('study-max').value);
  const shown = study.records.filter((r) => {
    if (!r.ok || !Number.isFinite(r.metrics[xName]) || !Number.isFinite(r.metrics[yName])) return false;
    if (!filter) return true;
    const v = r.metrics[filter];
    return Number.isFinite(v) && !(Number.isFinite(lo) && v < lo) && !(Number.isFinite(hi) && v > hi);
  });
  const W = 640, H = 400, L = 70, R = 16, T = 14, B = 46;
  const xs = shown.map((r) => r.metrics[xName]), ys = shown.map((r) => r.metrics[yName]);
  const [x0, x1] = extent(xs), [y0, y1] = extent(ys);
  const x = (v) => L + ((v - x0) / (x1 - x0)) * (W - L - R);
  const y = (v) => H - B - ((v - y0) / (y1 - y0)) * (H - T - B);
  const svg = svgEl('svg', { viewBox: `0 0 ${W} ${H}`, role: 'group', 'aria-label': `Designs: ${yName} against ${xName}; front points are buttons that load the design` });
  axes(svg, { W, H, L, R, T, B }, [x0, x1, x, xName], [y0, y1, y, yName]);
  for (const c of study.constraints) {
    for (const [bound, value] of [['min', c.min], ['max', c.max]]) {
      if (value === null || value === undefined) continue;
      if (c.metric === xName) svg.append(svgEl('line', { x1: x(value), y1: T, x2: x(value), y2: H - B, stroke: '#b3261e', 'stroke-dasharray': '5 4' }, `${c.metric} ${bound}`));
      if (c.metric === yName) svg.append(svgEl('line', { x1: L, y1: y(value), x2: W - R, y2: y(value), stroke: '#b3261e', 'stroke-dasharray': '5 4' }));
    }
  }
  const ordered = [...shown].sort((a, b) => Number(a.on_front) - Number(b.on_front));
  for (const r of ordered) svg.append(studyPoint(r, x(r.metrics[xName]), y(r.metrics[yName]), xName, yName));
  document.getElementById('study-plot').replaceChildren(svg);
}

function extent(values) {
  if (!values.length) return [0, 1];
  let lo = Math.min(...values), hi = Math.max(...values);
  if (hi - lo < 1e-12 * Math.max(1, Math.abs(hi))) { lo -= 0.5; hi += 0.5; }
  const pad = 0.05 * (hi - lo);
  return [lo - pad, hi + pad];
}

function studyPoint(record, cx, cy, xName, yName) {
  const label = `design ${record.index + 1}${record.on_front ? ' (front)' : ''}: ${xName} ${fmt(record.metrics[xName], 4)}, ${yName} ${fmt(record.metrics[yName], 4)}`;
  const point = svgEl('circle', { cx: cx.toFixed(1), cy: cy.toFixed(1), r: record.on_front ? 6 : 4, fill: record.on_front ? '#d55e00' : '#8a96a3', class: 'point', 'data-index': record.index, 'data-front': record.on_front ? '1' : '0' });
  point.append(svgEl('title', {}, label));
  if (record.on_front) {
    point.setAttribute('tabindex', '0');
    point.setAttribute('role', 'button');
    point.setAttribute('aria-label', `${label}; load it`);
  }
  const describe = () => {
    const variables = Object.entries(record.variables).map(([k, v]) => `${k} = ${fmt(v, 4)}`).join(', ');
    document.getElementById('study-hover').textContent = `${label}. ${variables}`;
  };
  point.addEventListener('mouseenter', describe);
  point.addEventListener('focus', describe);
  const load = async () => {
    const spec = await api('GET', `/api/study/spec?index=${record.index}`);
    await send({ text: spec.text });
    say(`Loaded design ${record.index + 1} of the study into the editor.`);
  };
  point.addEventListener('click', load);
  point.addEventListener('keydown', (e) => { if (e.key === 'Enter' || e.key === ' ') { e.preventDefault(); load(); } });
  return point;
}

// --- start ----------------------------------------------------------------------------------
async function poll() {
  for (;;) {
    try {
      render(await api('GET', sessionPath(`?after=${studio.revision}`)));
    } catch (e) {
      say(`Lost the server: ${e.message}. Reload the page once it runs again.`);
      await new Promise((r) => setTimeout(r, 2000));
    }
  }
}

function wire() {
  let timer = null;
  const area = document.getElementById('toml');
  area.addEventListener('input', () => {
    clearTimeout(timer);
    timer = setTimeout(() => { studio.sentText = area.value; send({ text: area.value }); }, 350);
  });
  for (const button of document.querySelectorAll('[data-analysis]')) {
    button.addEventListener('click', () => ask(`/analyses/${button.dataset.analysis}`));
  }
  document.getElementById('analyses-cancel').addEventListener('click', () => ask('/analyses/cancel'));
  document.getElementById('undo').addEventListener('click', () => send({ action: 'undo' }));
  document.getElementById('redo').addEventListener('click', () => send({ action: 'redo' }));
  document.getElementById('pin').addEventListener('click', async () => {
    try { render(await api('POST', sessionPath('/pin'), {})); } catch (e) { say(e.message); }
  });
  document.addEventListener('keydown', (e) => {
    const inText = e.target && (e.target.tagName === 'TEXTAREA' || e.target.tagName === 'INPUT');
    if ((e.ctrlKey || e.metaKey) && !inText && e.key === 'z') { e.preventDefault(); send({ action: e.shiftKey ? 'redo' : 'undo' }); }
  });
}

async function start() {
  wire();
  try {
    [studio.schema, studio.info] = await Promise.all([api('GET', '/api/schema'), api('GET', '/api/info')]);
    buildForm(studio.schema);
    render(await api('POST', '/api/sessions'));
    document.body.dataset.ready = '1';
    if (studio.info.study) setupStudy(await api('GET', '/api/study'));
  } catch (e) {
    say(`The studio could not start: ${e.message}`);
    return;
  }
  poll();
}

start();
