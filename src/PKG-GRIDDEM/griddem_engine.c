/* The GRIDDEM engine; see griddem_engine.h. */
#include "griddem_engine.h"

#include <math.h>
#include <string.h>

void griddem_engine_init(griddem_engine *e, int history_values)
{
  memset(e, 0, sizeof(*e));
  griddem_history_init(&e->hist, history_values);
}

void griddem_engine_free(griddem_engine *e)
{
  griddem_bins_free(&e->bins);
  griddem_channels_free(&e->channels);
  griddem_history_free(&e->hist);
  memset(e, 0, sizeof(*e));
}

int griddem_engine_step(griddem_engine *e, const griddem_step *s, griddem_sweep_result *result,
                        int *coarsened)
{
  const griddem_particles *p = &s->particles;
  memset(result, 0, sizeof(*result));
  *coarsened = griddem_grid_cover(&e->grid, s->anchor, p->nall, p->x, s->cell_edge, s->max_cells);
  if (griddem_bin_points(&e->bins, &e->grid, p->nall, p->x, p->tag, p->tag_bytes) != 0 ||
      griddem_channels_fill(&e->channels, &e->bins, p) != 0) {
    result->fault = GRIDDEM_FAULT_MEMORY;
    return result->fault;
  }
  griddem_sweep(&e->grid, &e->bins, &e->channels, p->nlocal, s->rmax, s->model, s->excl, s->dt,
                s->history_update, &e->hist, s->row_of, s->f, s->torque, s->vatom, s->want_virial,
                result);
  /* the history's row of sorted slot s is s */
  if (s->model->track_contacts)
    for (int k = 0; k < e->bins.n; k++)
      if (e->bins.order[k] < p->nlocal) s->row_of[e->bins.order[k]] = k;

  /* how far the fastest owned particle moves in a step, in cells */
  e->stats.max_speed = sqrt(e->channels.vmax2);
  e->stats.max_cells_moved = e->stats.max_speed * s->dt / e->grid.h;
  e->stats.nonfinite_velocity = e->channels.nonfinite;
  e->stats.occupied_cells = e->bins.occupied;
  e->stats.max_occupancy = e->bins.max_occupancy;
  e->stats.cell_edge = e->grid.h;
  e->stats.contacts = result->contacts;
  e->stats.max_contacts = result->max_contacts;
  e->stats.elastic_energy = result->energy;
  return result->fault;
}

int griddem_engine_reserve(griddem_engine *e, int n, int contacts)
{
  return griddem_history_reserve(&e->hist, n, (long) n * contacts);
}

double griddem_engine_memory(const griddem_engine *e)
{
  const griddem_channels *ch = &e->channels;
  return (double) e->bins.ncell_cap * sizeof(int) + (double) e->bins.n_cap * (sizeof(int) + sizeof(long)) +
      (double) ch->cap * (4 * sizeof(double) + sizeof(griddem_slot_state) + sizeof(griddem_slot_sum) +
                          sizeof(int64_t) + sizeof(int)) +
      griddem_history_memory(&e->hist);
}

int griddem_engine_history_values(const griddem_engine *e)
{
  return e->hist.values;
}

int griddem_engine_set_history_values(griddem_engine *e, int values)
{
  return griddem_history_set_values(&e->hist, values);
}

int griddem_engine_row_length(const griddem_engine *e, int row)
{
  return 1 + griddem_history_count(&e->hist, row) * GRIDDEM_HISTORY_ENTRY(e->hist.values);
}

int griddem_engine_max_row_length(const griddem_engine *e)
{
  return 1 + e->hist.max_count * GRIDDEM_HISTORY_ENTRY(e->hist.values);
}

int griddem_engine_get_row(const griddem_engine *e, int row, double *buf)
{
  const int count = griddem_history_count(&e->hist, row);
  const int n = count * GRIDDEM_HISTORY_ENTRY(e->hist.values);
  buf[0] = count;
  memcpy(buf + 1, griddem_history_row(&e->hist, row), sizeof(double) * (size_t) n);
  return n + 1;
}

int griddem_engine_put_row(griddem_engine *e, const double *buf, int values)
{
  return griddem_history_add_row(&e->hist, (int) buf[0], buf + 1, values);
}

const double *griddem_engine_find(const griddem_engine *e, int row, double partner)
{
  return griddem_history_find(&e->hist, row, partner);
}
