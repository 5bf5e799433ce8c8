/* The engine's face: a step bins, sweeps and points each owned particle at its new row of the
 * history it is given; rows travel as messages (count, then tag and values per contact) that
 * put_message takes back unchanged, also across a change of values per contact; the longest
 * message is known; the step's statistics count contacts, the fastest motion and non-finite
 * velocities. */
#include "check.h"
#include "griddem_engine.h"
#include "spec_text.h"

int main(void)
{
  griddem_pair_params table[4];
  const griddem_pair_params law = law_from_text("hooke 1e3 0 damping mass_velocity tangential gran/hooke/history 300 0 0.5");
  for (int k = 0; k < 4; k++) table[k] = law;
  griddem_model m;
  memset(&m, 0, sizeof(m));
  m.ntypes = 1, m.pair = table, m.history_size = 3, m.track_contacts = 1;
  for (int k = 0; k < 3; k++) m.history_parity[k] = -1.0;

  /* a row of three: particle 0 between 1 and 2, 3 apart; 2 and 3 are ghosts */
  double x[12] = {0, 0, 0, 0.9, 0, 0, -0.9, 0, 0, 5, 5, 5}, v[12] = {0, 1, 0, 0, -1, 0, 0, 0, 2, 3, 0, 0};
  double w[12] = {0}, rad[4] = {0.5, 0.5, 0.5, 0.5}, mass[4] = {1, 1, 1, 1}, f[12] = {0}, t[12] = {0};
  int tag[4] = {7, 8, 9, 10}, type[4] = {1, 1, 1, 1}, mask[4] = {1, 1, 1, 1}, row_of[4] = {-1, -1, -1, -1};
  griddem_engine e;
  griddem_engine_init(&e);
  griddem_history h;
  griddem_history_init(&h, 3);
  griddem_step s;
  memset(&s, 0, sizeof(s));
  griddem_particles part = {2, 4, x, v, w, rad, mass, tag, 4, type, mask, 0};
  s.particles = part;
  s.cell_edge = griddem_cell_edge(GRIDDEM_CELL_AUTO, 0.5, 0.5, 0.0);
  s.max_cells = 100000, s.rmax = 0.5, s.model = &m, s.dt = 1e-2, s.history_update = 1;
  s.hist = &h, s.row_of = row_of, s.f = f, s.torque = t;
  griddem_sweep_result r;
  int coarsened;
  CHECK(griddem_engine_step(&e, &s, &r, &coarsened) == GRIDDEM_FAULT_NONE && !coarsened, "step runs");
  CHECK(e.stats.contacts == 3 && e.stats.max_contacts == 2, "contacts %ld, most %d", e.stats.contacts, e.stats.max_contacts);
  CHECK(e.stats.nonfinite_velocity == 0, "velocities finite");
  CHECK_CLOSE(e.stats.max_speed, 1.0, 1e-15, 0.0);
  CHECK_CLOSE(e.stats.max_cells_moved, 1.0 * 1e-2 / e.stats.cell_edge, 1e-15, 0.0);
  CHECK(row_of[0] >= 0 && row_of[1] >= 0 && row_of[2] == -1, "owned particles have rows, ghosts none");
  CHECK(griddem_history_longest_message(&h) == 1 + 2 * 4, "longest message: %d", griddem_history_longest_message(&h));

  /* particle 0's row as a message, appended back: same contacts, same values */
  double msg[64], again[64];
  const int n = griddem_history_get_message(&h, row_of[0], msg);
  CHECK(n == griddem_history_message_length(&h, row_of[0]) && msg[0] == 2.0, "message of %d doubles, %g contacts", n, msg[0]);
  const int row = griddem_history_put_message(&h, msg, 3);
  CHECK(row >= 0 && griddem_history_get_message(&h, row, again) == n && memcmp(msg, again, sizeof(double) * n) == 0,
        "a row put back reads the same");
  const double *h8 = griddem_history_find(&h, row_of[0], 8), *h9 = griddem_history_find(&h, row_of[0], 9);
  CHECK(h8 && h9 && h8[1] != 0.0 && h9[2] != 0.0, "shear of both contacts stored");
  CHECK(griddem_history_find(&h, row_of[0], 10) == NULL, "no entry for a partner not touched");
  /* a row written with 3 values read by an engine keeping 4: values kept, the 4th zero */
  CHECK(griddem_history_set_values(&h, 4) == 0, "convert to 4 values");
  const int row4 = griddem_history_put_message(&h, msg, 3);
  CHECK(griddem_history_get_message(&h, row4, again) == 1 + 2 * 5 && again[1] == msg[1] && again[2] == msg[2] &&
            again[4] == msg[4] && again[5] == 0.0, "message converted to 4 values per contact");
  CHECK(griddem_engine_memory(&e) > 0.0, "memory reported");
  /* a non-finite velocity of an owned particle is flagged (a ghost's is its owner's business) */
  v[9] = INFINITY;
  griddem_engine_step(&e, &s, &r, &coarsened);
  CHECK(e.stats.nonfinite_velocity == 0, "a ghost's infinite velocity is not flagged");
  v[3] = NAN;
  griddem_engine_step(&e, &s, &r, &coarsened);
  CHECK(e.stats.nonfinite_velocity == 1, "an owned particle's NaN velocity is flagged");

  /* the first pass: the box of every position, speed and radii of the owned particles only, the
     first non-finite position */
  v[3] = 0.0;
  rad[3] = 2.0, rad[1] = 0.25;
  griddem_scan scan;
  griddem_engine_scan(&part, &scan);
  CHECK(scan.first_nonfinite == -1, "positions finite");
  CHECK(scan.lo[0] == -0.9 && scan.hi[0] == 5.0 && scan.lo[1] == 0.0 && scan.hi[2] == 5.0, "box of all four");
  CHECK(scan.vmax2 == 1.0 && scan.nonfinite_velocity == 0, "fastest owned speed^2 %g (the ghosts' 2 and 3 left out)",
        scan.vmax2);
  CHECK(scan.rmin == 0.25 && scan.rmax == 0.5, "radius range of the owned: %g %g", scan.rmin, scan.rmax);
  x[7] = NAN, x[11] = INFINITY;
  griddem_engine_scan(&part, &scan);
  CHECK(scan.first_nonfinite == 2, "first non-finite position: particle %d", scan.first_nonfinite);
  griddem_engine_free(&e);
  griddem_history_free(&h);
  return check_summary();
}
