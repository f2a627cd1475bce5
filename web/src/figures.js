// The figures beside the model: sizes, area, volume, the checks of `vdbmesh check` and the
// meshing time, and the table of the meshes made so far (to compare methods side by side).

const number = (value, digits = 4) => Number(value).toPrecision(digits);
const count = (value) => Number(value).toLocaleString('en-US');
const yesNo = (ok, yes = 'yes', no = 'no') => `<span class="${ok ? 'good' : 'bad'}">${ok ? yes : no}</span>`;

function rows(table, entries) {
  table.innerHTML = entries.map(([name, value]) => `<tr><td>${name}</td><td>${value}</td></tr>`).join('');
}

/// Counts of a mesh on screen, before its analysis arrives.
export function showCounts(table, mesh, note) {
  rows(table, [
    ['triangles', `<span id="triangle-count">${count(mesh.triangles)}</span>`],
    ['vertices', count(mesh.vertices)],
    ['meshing time', `${number(mesh.seconds, 3)} s`],
    ['', note],
  ]);
}

/// The full analysis (GET /api/figures), with a @a note under it.
export function showFigures(table, figures, note) {
  const check = figures.check;
  const manifold = check.nonmanifold_edges === 0 && check.nonmanifold_vertices === 0;
  rows(table, [
    ['triangles', `<span id="triangle-count">${count(figures.triangles)}</span>`],
    ['vertices', count(figures.vertices)],
    ['area', number(check.area)],
    ['volume', number(check.volume)],
    ['closed', yesNo(check.closed)],
    ['manifold', yesNo(manifold)],
    ['self-intersections', yesNo(check.self_intersecting_pairs === 0, 'none', count(check.self_intersecting_pairs))],
    ['components', count(check.components)],
    ['meshing time', `${number(figures.seconds, 3)} s`],
    ['', note],
  ]);
}

/// One line per full mesh made: method, its parameter, isovalue, triangles, seconds.
export function addHistory(table, params, mesh) {
  const parameter = params.method === 'dc' ? `error ${params.error}` : params.method === 'openvdb' ? `adapt. ${params.adaptivity}` : '';
  const row = `<tr><td>${params.method} ${parameter} @ ${number(params.iso)}</td><td>${count(mesh.triangles)} · ${number(mesh.seconds, 2)} s</td></tr>`;
  table.insertAdjacentHTML('afterbegin', row);
  while (table.rows.length > 8) table.deleteRow(-1);
}
