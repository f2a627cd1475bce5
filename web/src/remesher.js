// Live re-meshing: for a scan, the coarse mesh first, then the full one (or, over the
// triangle budget, its count and a button), then its figures. A newer request makes older
// ones moot: their answers are dropped. Times are measured from the request to the buffers
// received (*FetchedMs), to the frame that shows the mesh (*Ms), and, over the budget, to
// the full mesh's count received (overBudgetMs: the server has made it).
import { fetchJson, fetchMesh, meshQuery, OverBudget } from './mesh_loader.js';

export class Remesher {
  /// @param handlers {onMesh(mesh, level), onOverBudget(triangles, estimated), onFigures(figures)}
  /// @param drawn () => a promise of the next frame drawn
  constructor(isScan, budget, handlers, drawn) {
    this.drawn = drawn;
    this.isScan = isScan;
    this.budget = budget;
    this.handlers = handlers;
    this.generation = 0;
  }

  /// Meshes with @a params ({method, iso, error, adaptivity}); @a withinBudget false fetches
  /// the full mesh whatever its size. Resolves with the timings, or null when overtaken.
  async run(params, withinBudget = true) {
    const generation = ++this.generation;
    this.abort?.abort();
    const abort = (this.abort = new AbortController());
    const current = () => generation === this.generation;
    const start = performance.now();
    const timings = { params };
    try {
      if (this.isScan && withinBudget) {
        const coarse = await fetchMesh({ ...params, level: 'coarse' }, abort.signal);
        if (!current()) return null;
        timings.coarseFetchedMs = performance.now() - start;
        this.handlers.onMesh(coarse, 'coarse');
        await this.drawn();
        timings.coarseMs = performance.now() - start;
      }
      const limit = withinBudget && this.isScan ? this.budget : undefined;
      const full = await fetchMesh({ ...params, level: 'full', max_triangles: limit }, abort.signal);
      if (!current()) return null;
      timings.fullFetchedMs = performance.now() - start;
      this.handlers.onMesh(full, 'full', params);
      await this.drawn();
      timings.fullMs = performance.now() - start;
    } catch (error) {
      if (!current() || error.name === 'AbortError') return null;
      if (!(error instanceof OverBudget)) throw error;
      timings.overBudgetMs = performance.now() - start;
      this.handlers.onOverBudget(error.triangles, error.estimated);
      if (error.estimated) return timings;  // the server makes no full mesh, nor its figures
    }
    const figures = await fetchJson(`/api/figures?${meshQuery({ ...params, level: 'full' })}`, abort.signal);
    if (current()) this.handlers.onFigures(figures);
    return timings;
  }
}
