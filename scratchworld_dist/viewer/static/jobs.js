/*
 * The jobs table of a run: filters, a search box, sorting by any column and pages of 100 rows,
 * over the data jobs-data.js defines (window.scratchworldJobs: {columns, rows}). The filter
 * lives in the URL's hash (#outcome=failed&mode=primitive), so links can point at a selection.
 * Cells are written as text (textContent), never as HTML: task ids and messages are user data.
 */
(function () {
  'use strict';

  const PAGE_SIZE = 100;
  const data = window.scratchworldJobs || {columns: [], rows: []};
  const col = {};
  data.columns.forEach((name, i) => { col[name] = i; });
  const table = document.getElementById('jobs');
  const body = table.querySelector('tbody');
  const selects = Array.from(document.querySelectorAll('#filters select[data-column]'));
  const search = document.getElementById('search');
  const state = {filters: {}, search: '', sort: 'task_id', descending: false, page: 0};

  const text = (value) => (value === null || value === undefined ? '' : String(value));

  function readHash() {
    const params = new URLSearchParams(window.location.hash.slice(1));
    state.filters = {};
    selects.forEach((select) => {
      const value = params.get(select.dataset.column);
      if (value !== null) state.filters[select.dataset.column] = value;
    });
    state.search = params.get('q') || '';
    state.sort = params.get('sort') || 'task_id';
    state.descending = params.get('desc') === '1';
    state.page = Math.max(0, parseInt(params.get('page') || '0', 10) || 0);
  }

  function writeHash() {
    const params = new URLSearchParams();
    Object.keys(state.filters).forEach((name) => params.set(name, state.filters[name]));
    if (state.search) params.set('q', state.search);
    if (state.sort !== 'task_id') params.set('sort', state.sort);
    if (state.descending) params.set('desc', '1');
    if (state.page) params.set('page', String(state.page));
    const hash = params.toString();
    window.history.replaceState(null, '', hash ? '#' + hash : window.location.pathname + window.location.search);
  }

  function fillSelects() {
    selects.forEach((select) => {
      const i = col[select.dataset.column];
      const counts = new Map();
      data.rows.forEach((row) => { const v = text(row[i]); counts.set(v, (counts.get(v) || 0) + 1); });
      if (counts.size === 1 && counts.has('')) { select.parentElement.hidden = true; return; }
      Array.from(counts.keys()).sort().forEach((value) => {
        const option = document.createElement('option');
        option.value = value;
        option.textContent = `${value === '' ? '(none)' : value} (${counts.get(value)})`;
        select.appendChild(option);
      });
    });
  }

  function matches(row) {
    for (const name of Object.keys(state.filters)) {
      if (text(row[col[name]]) !== state.filters[name]) return false;
    }
    if (!state.search) return true;
    const needle = state.search.toLowerCase();
    return ['task_id', 'job_id', 'model', 'agent', 'error_class', 'error_message']
      .some((name) => text(row[col[name]]).toLowerCase().includes(needle));
  }

  function compare(a, b) {
    const i = col[state.sort];
    const x = a[i], y = b[i];
    let order;
    if (typeof x === 'number' && typeof y === 'number') order = x - y;
    else if (x === null || x === undefined) order = (y === null || y === undefined) ? 0 : 1;
    else if (y === null || y === undefined) order = -1;
    else order = text(x).localeCompare(text(y), undefined, {numeric: true});
    return state.descending ? -order : order;
  }

  function cell(row, name) {
    const v = row[col[name]];
    if (name === 'tests_passed') return `${text(v)}/${text(row[col.tests_total])}`;
    if (name === 'cost_usd') return `$${(v || 0).toFixed(4)}`;
    if (name === 'episode_s') return (v || 0).toFixed(1);
    return text(v);
  }

  function render() {
    const shown = data.rows.filter(matches).sort(compare);
    const pages = Math.max(1, Math.ceil(shown.length / PAGE_SIZE));
    state.page = Math.min(state.page, pages - 1);
    const outcomes = {};
    shown.forEach((row) => { const o = row[col.outcome]; outcomes[o] = (outcomes[o] || 0) + 1; });
    const summary = Object.keys(outcomes).sort().map((o) => `${o} ${outcomes[o]}`).join(' · ');
    document.getElementById('counts').textContent =
      `${shown.length} of ${data.rows.length} jobs${summary ? ' · ' + summary : ''}`;
    document.getElementById('page').textContent = `page ${state.page + 1} of ${pages}`;
    document.getElementById('prev').disabled = state.page === 0;
    document.getElementById('next').disabled = state.page >= pages - 1;
    const columns = Array.from(table.querySelectorAll('th[data-sort]')).map((th) => th.dataset.sort);
    const fragment = document.createDocumentFragment();
    shown.slice(state.page * PAGE_SIZE, (state.page + 1) * PAGE_SIZE).forEach((row) => {
      const tr = document.createElement('tr');
      tr.className = text(row[col.outcome]);
      columns.forEach((name) => {
        const td = document.createElement('td');
        if (name === 'task_id') {
          const a = document.createElement('a');
          a.href = `jobs/${encodeURIComponent(text(row[col.job_id]))}.html`;
          a.textContent = text(row[col.task_id]);
          td.appendChild(a);
        } else {
          td.textContent = cell(row, name);
        }
        if (name === 'error_class' && row[col.error_message]) td.title = text(row[col.error_message]);
        tr.appendChild(td);
      });
      fragment.appendChild(tr);
    });
    body.replaceChildren(fragment);
    table.querySelectorAll('th[data-sort]').forEach((th) => {
      th.setAttribute('aria-sort', th.dataset.sort === state.sort ? (state.descending ? 'descending' : 'ascending') : 'none');
    });
    selects.forEach((select) => { select.value = state.filters[select.dataset.column] || ''; });
    search.value = state.search;
  }

  function update() { writeHash(); render(); }

  selects.forEach((select) => select.addEventListener('change', () => {
    if (select.value) state.filters[select.dataset.column] = select.value;
    else delete state.filters[select.dataset.column];
    state.page = 0;
    update();
  }));
  search.addEventListener('input', () => { state.search = search.value; state.page = 0; update(); });
  document.getElementById('clear').addEventListener('click', () => {
    state.filters = {}; state.search = ''; state.page = 0; update();
  });
  document.getElementById('prev').addEventListener('click', () => { state.page -= 1; update(); });
  document.getElementById('next').addEventListener('click', () => { state.page += 1; update(); });
  table.querySelectorAll('th[data-sort]').forEach((th) => {
    const sort = () => {
      state.descending = state.sort === th.dataset.sort ? !state.descending : false;
      state.sort = th.dataset.sort;
      update();
    };
    th.addEventListener('click', sort);
    th.addEventListener('keydown', (event) => { if (event.key === 'Enter') sort(); });
  });
  window.addEventListener('hashchange', () => { readHash(); render(); });

  fillSelects();
  readHash();
  render();
  table.dataset.ready = 'true';
})();
