'use strict';
// rdsim dashboard page (served by src/dashboard/dashboard_server.cpp). It follows each selected
// run's progress.csv (and eval.csv, a run's evaluations) through /api/progress, which answers only
// the rows written since the byte offset it last returned, and draws one uPlot chart per metric with
// the selected runs overlaid.
// window.rdsimDashboard says what was last drawn (the headless-browser test reads it).

const CHARTS = [
  {column: 'mean_return', title: 'Mean return'},
  {column: 'success_rate', title: 'Success rate'},
  {column: 'mean_length', title: 'Episode length'},
  {column: 'policy_loss', title: 'Policy loss'},
  {column: 'value_loss', title: 'Value loss'},
  {column: 'loss', title: 'TD loss'},
  {column: 'entropy', title: 'Entropy'},
  {column: 'approx_kl', title: 'Approximate KL'},
  {column: 'steps_per_s', title: 'Steps/s'},
  // eval.csv (a run with "eval"): drawn against timesteps, its only x
  {column: 'mean_return', log: 'eval', title: 'Evaluation: mean return'},
  {column: 'success_rate', log: 'eval', title: 'Evaluation: success rate'},
];
const chartId = (spec) => (spec.log ? `${spec.log}:` : '') + spec.column;
const COLORS = ['#1f77b4', '#d62728', '#2ca02c', '#ff7f0e', '#9467bd',
                '#8c564b', '#e377c2', '#17becf', '#7f7f7f', '#bcbd22'];
const SELECTED_AT_START = 10;  // runs shown without a click; more are listed, unticked
const RUNS_REFRESH_MS = 5000;  // how often the list of runs is asked for again
const MAX_PAGES = 50;          // answers per run per poll while the server says "more"

const state = {
  runs: new Map(),    // id -> run (see addRun)
  charts: new Map(),  // chartId(spec) -> {plot, key, el}
  pollMs: 500,
  runsFetchedAt: 0,
  dirty: false,
};
const report = window.rdsimDashboard = {draws: 0, drawnAt: 0, lastX: {}, rows: {}, evalRows: {}, charts: 0, errors: []};

const $ = (id) => document.getElementById(id);

function setStatus(text, isError) {
  const el = $('status');
  el.textContent = text;
  el.classList.toggle('error', !!isError);
}

async function getJson(url) {
  const response = await fetch(url, {cache: 'no-store'});
  let body = null;
  try {
    body = await response.json();
  } catch (e) {
    throw new Error(`${url}: HTTP ${response.status}, not JSON`);
  }
  if (!response.ok) throw new Error((body && body.error) || `HTTP ${response.status}`);
  return body;
}

function addRun(info) {
  const run = {
    id: info.id,
    label: String(info.label || info.id),
    meta: [info.algorithm, info.env, info.seed != null ? `seed ${info.seed}` : ''].filter(Boolean).join(' · '),
    color: COLORS[state.runs.size % COLORS.length],
    selected: state.runs.size < SELECTED_AT_START,
    columns: [],
    cols: {},      // column name -> array of numbers (null: empty cell)
    rows: 0,
    next: 0,       // byte offset to ask from
    skipped: 0,    // malformed rows the server passed over
    error: null,
    evalLog: {columns: [], cols: {}, rows: 0, next: 0, skipped: 0},  // eval.csv, the same fields
  };
  state.runs.set(run.id, run);
  return run;
}

// `table`: a run (its progress.csv) or its evalLog.
function clearRows(table, columns) {
  table.columns = columns.slice();
  table.cols = {};
  for (const c of table.columns) table.cols[c] = [];
  table.rows = 0;
  table.skipped = 0;
}

async function refreshRuns() {
  const body = await getJson('api/runs');
  if (Number.isFinite(body.poll_ms) && body.poll_ms >= 50) state.pollMs = body.poll_ms;
  let added = false;
  for (const info of body.runs || []) {
    if (info && typeof info.id === 'string' && !state.runs.has(info.id)) {
      addRun(info);
      added = true;
    }
  }
  state.runsFetchedAt = Date.now();
  if (added) renderRunList();
}

function sameColumns(a, b) {
  return a.length === b.length && a.every((c, i) => c === b[i]);
}

// Appends the rows of the run's log (progress or eval) written since table.next; a rewritten file
// (resumed run) starts the table over.
async function fetchRows(run, table = run, log = 'progress') {
  for (let page = 0; page < MAX_PAGES; ++page) {
    const body = await getJson(`api/progress?run=${encodeURIComponent(run.id)}&log=${log}&from=${table.next}`);
    const columns = Array.isArray(body.columns) ? body.columns : [];
    const rows = Array.isArray(body.rows) ? body.rows : [];
    if (columns.length === 0) return;  // no header yet
    if (body.restarted || !sameColumns(table.columns, columns)) clearRows(table, columns);
    for (const row of rows) {
      if (!Array.isArray(row) || row.length !== columns.length) continue;
      for (let i = 0; i < columns.length; ++i) {
        const v = row[i];
        table.cols[columns[i]].push(typeof v === 'number' && Number.isFinite(v) ? v : null);
      }
      table.rows += 1;
    }
    if (rows.length > 0) state.dirty = true;
    table.skipped += Number(body.skipped) || 0;
    if (Number.isSafeInteger(body.next)) table.next = body.next;
    if (!body.more) return;
  }
}

function renderRunList() {
  const list = $('runs');
  list.textContent = '';
  if (state.runs.size === 0) {
    const li = document.createElement('li');
    li.className = 'note';
    li.textContent = 'no runs yet (a run folder holds progress.csv)';
    list.appendChild(li);
    return;
  }
  for (const run of state.runs.values()) {
    const li = document.createElement('li');
    const label = document.createElement('label');
    const box = document.createElement('input');
    box.type = 'checkbox';
    box.checked = run.selected;
    box.addEventListener('change', () => {
      run.selected = box.checked;
      state.dirty = true;
      poll.now();
    });
    const swatch = document.createElement('span');
    swatch.className = 'swatch';
    swatch.style.background = run.color;
    const text = document.createElement('span');
    const name = document.createElement('div');
    name.className = 'run-name';
    name.textContent = run.label;
    const meta = document.createElement('div');
    meta.className = 'run-meta';
    run.metaEl = meta;
    const error = document.createElement('div');
    error.className = 'run-error';
    run.errorEl = error;
    text.append(name, meta, error);
    label.append(box, swatch, text);
    li.appendChild(label);
    list.appendChild(li);
  }
  updateRunNotes();
}

function updateRunNotes() {
  for (const run of state.runs.values()) {
    if (!run.metaEl) continue;
    const skipped = run.skipped ? `, ${run.skipped} malformed skipped` : '';
    run.metaEl.textContent = `${run.meta}${run.meta ? ' · ' : ''}${run.rows} rows${skipped}`;
    run.errorEl.textContent = run.error || '';
  }
}

// TensorBoard's smoothing: an exponential moving average, corrected for its start at zero.
function smooth(ys, weight, logScale) {
  if (weight <= 0 && !logScale) return ys;
  const out = new Array(ys.length);
  let last = 0;
  let norm = 0;
  for (let i = 0; i < ys.length; ++i) {
    const y = ys[i];
    if (y === null || (logScale && y <= 0)) {
      out[i] = null;
      continue;
    }
    if (weight <= 0) {
      out[i] = y;
      continue;
    }
    last = last * weight + (1 - weight) * y;
    norm = norm * weight + (1 - weight);
    out[i] = last / norm;
  }
  return out;
}

// [xs, ys] without the rows whose x is missing (uPlot wants x ascending and present).
function series(table, xName, column, weight, logScale) {
  const xs = table.cols[xName];
  const ys = smooth(table.cols[column], weight, logScale);
  if (!xs.includes(null)) return [xs, ys];
  const fx = [];
  const fy = [];
  for (let i = 0; i < xs.length; ++i) {
    if (xs[i] !== null) {
      fx.push(xs[i]);
      fy.push(ys[i]);
    }
  }
  return [fx, fy];
}

function chartWidth(el) {
  return Math.max(300, el.clientWidth - 8);
}

// Charts follow their grid cell's width (the grid settles after the first charts appear).
const resizer = new ResizeObserver((entries) => {
  for (const entry of entries) {
    for (const chart of state.charts.values()) {
      if (chart.el === entry.target && chart.plot.width !== chartWidth(chart.el)) {
        chart.plot.setSize({width: chartWidth(chart.el), height: 260});
      }
    }
  }
});

function makeChart(spec, runs, xName, logScale, data) {
  const old = state.charts.get(chartId(spec));
  let el = old && old.el;
  if (old) old.plot.destroy();
  if (!el) {
    el = document.createElement('div');
    el.className = 'chart';
    el.dataset.column = chartId(spec);
    $('charts').appendChild(el);
    resizer.observe(el);
  }
  const opts = {
    title: spec.title,
    width: chartWidth(el),
    height: 260,
    scales: {x: {time: false}, y: {distr: logScale ? 3 : 1}},
    axes: [{label: xName === 'wall_time' ? 'wall time (s)' : 'timesteps'}, {size: 64}],
    series: [{label: xName}].concat(runs.map((r) => ({
      label: r.label, stroke: r.color, width: 1.5, spanGaps: true, points: {show: false},
    }))),
    cursor: {sync: {key: 'rdsim'}},
  };
  const plot = new uPlot(opts, data, el);
  return {plot, el};
}

function draw() {
  state.dirty = false;
  const xName = $('x-axis').value;
  const weight = Number($('smoothing').value) || 0;
  const logScale = $('log-scale').checked;
  const shown = [...state.runs.values()].filter((r) => r.selected && r.cols[xName]);
  const order = [];
  for (const spec of CHARTS) {
    const id = chartId(spec);
    const tableOf = (r) => (spec.log === 'eval' ? r.evalLog : r);
    const x = spec.log === 'eval' ? 'timesteps' : xName;
    const runs = shown.filter((r) => tableOf(r).cols[spec.column] && tableOf(r).cols[x] && tableOf(r).rows > 0);
    const old = state.charts.get(id);
    if (runs.length === 0) {
      if (old) {
        old.plot.destroy();
        resizer.unobserve(old.el);
        old.el.remove();
        state.charts.delete(id);
      }
      continue;
    }
    const tables = runs.map((r) => series(tableOf(r), x, spec.column, weight, logScale));
    const data = tables.length === 1 ? tables[0] : uPlot.join(tables);
    const key = [x, logScale, ...runs.map((r) => r.id)].join('|');
    if (old && old.key === key) {
      old.plot.setData(data);
    } else {
      const chart = makeChart(spec, runs, x, logScale, data);
      state.charts.set(id, {plot: chart.plot, el: chart.el, key});
    }
    order.push(state.charts.get(id).el);
  }
  // Keep the charts in CHARTS order however they appeared.
  const container = $('charts');
  order.forEach((el, i) => {
    if (container.children[i] !== el) container.insertBefore(el, container.children[i] || null);
  });
  report.draws += 1;
  report.drawnAt = Date.now();
  report.charts = state.charts.size;
  for (const run of shown) {
    const xs = run.cols[xName];
    report.lastX[run.id] = xs.length ? xs[xs.length - 1] : null;
    report.rows[run.id] = run.rows;
    report.evalRows[run.id] = run.evalLog.rows;
  }
}

const poll = {
  timer: null,
  running: false,
  now() {
    clearTimeout(this.timer);
    this.timer = setTimeout(() => this.tick(), 0);
  },
  async tick() {
    if (this.running) return;
    this.running = true;
    const started = Date.now();
    try {
      if (state.runs.size === 0 || Date.now() - state.runsFetchedAt > RUNS_REFRESH_MS) await refreshRuns();
      const selected = [...state.runs.values()].filter((r) => r.selected);
      await Promise.all(selected.map((run) => fetchRows(run).then(() => fetchRows(run, run.evalLog, 'eval')).then(
        () => { run.error = null; },
        (e) => { run.error = e.message; })));
      const failed = selected.filter((r) => r.error).length;
      setStatus(`${state.runs.size} run${state.runs.size === 1 ? '' : 's'}` +
                `${failed ? `, ${failed} unreadable` : ''} · updated ${new Date().toLocaleTimeString()}`, false);
    } catch (e) {
      setStatus(`server unreachable (${e.message}); retrying`, true);
    }
    try {
      if (state.dirty) draw();
    } catch (e) {
      report.errors.push(String(e && e.stack || e));
      setStatus(`could not draw: ${e.message}`, true);
    }
    if (state.runs.size === 0) renderRunList();
    updateRunNotes();
    this.running = false;
    clearTimeout(this.timer);
    // A steady rate: the time spent fetching and drawing counts towards the interval.
    this.timer = setTimeout(() => this.tick(), Math.max(0, state.pollMs - (Date.now() - started)));
  },
};

function redrawAll() {
  for (const chart of state.charts.values()) chart.key = null;  // rebuild with the new options
  state.dirty = true;
  draw();
}

$('smoothing').addEventListener('input', () => {
  $('smoothing-value').textContent = Number($('smoothing').value).toFixed(2);
  state.dirty = true;
  draw();
});
$('log-scale').addEventListener('change', redrawAll);
$('x-axis').addEventListener('change', redrawAll);
poll.now();
