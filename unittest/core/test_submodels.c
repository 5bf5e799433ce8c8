/* The sub-model table: every row is reachable by its name and axis and says what its law keeps;
 * specs convert into parameters as pair granular's coeffs_to_local does (hertz/material's
 * 4/3 E_eff, mindlin's k NULL = 8 G_eff, tsuji's and coeff_restitution's damping); unlike types
 * mix as pair granular mixes them; the history layout (sizes, signs, offsets) follows the rows;
 * combinations stock refuses are refused with the sub-model named. */
#include "check.h"
#include "spec_text.h"

static void conversions(void)
{
  const double E = 1e6, nu = 0.3;
  griddem_pair_params p = law_from_text("hertz/material 1e6 0.8 0.3 damping tsuji tangential mindlin NULL 0.5 0.4");
  const double estar = E / (2.0 * (1.0 - nu * nu)), gstar = E / (4.0 * (2.0 - nu) * (1.0 + nu));
  CHECK_CLOSE(p.normal.k, 4.0 / 3.0 * estar, 1e-15, 0.0);
  CHECK_CLOSE(p.tangential.k, 8.0 * gstar, 1e-15, 0.0);
  /* Tsuji et al.'s fit at e = 0.8 */
  const double e = 0.8;
  const double tsuji = 1.2728 - 4.2783 * e + 11.087 * e * e - 22.348 * pow(e, 3) + 27.467 * pow(e, 4) -
      18.022 * pow(e, 5) + 4.8218 * pow(e, 6);
  CHECK_CLOSE(p.damping.damp, tsuji, 1e-12, 0.0);
  CHECK(p.need_contact_radius, "hertz and mindlin read the contact radius");
  /* linear spring: the damping ratio that gives e: 2 z = -2 ln e / sqrt(pi^2 + ln^2 e) */
  p = law_from_text("hooke 1e4 0.5 damping coeff_restitution tangential linear_nohistory 0.5 0.4");
  CHECK_CLOSE(p.damping.damp, -2.0 * log(0.5) / sqrt(M_PI * M_PI + log(0.5) * log(0.5)), 1e-15, 0.0);
  CHECK(!p.need_contact_radius, "hooke with coeff_restitution needs no contact radius");
  /* gran/hooke/history: damping meff*gamma_t, independent of the normal damping, own arithmetic */
  p = law_from_text("hooke 1e4 50 damping mass_velocity tangential gran/hooke/history 3e3 20 0.5");
  CHECK(p.tangential.xt == 0.0 && p.tangential.gamma_mass == 20.0 && p.tangential.k == 3e3 &&
        p.classic == 1, "gran/hooke/history parameters");
}

static void mixing(void)
{
  griddem_pair_spec a, b, m;
  spec_from_text("hertz/material 1e6 20 0.3 tangential mindlin NULL 0.5 0.4 rolling sds 100 2 0.1", &a);
  spec_from_text("hertz/material 4e6 5 0.2 tangential mindlin 2e4 0.2 0.1 rolling sds 400 8 0.4", &b);
  CHECK(griddem_spec_mix(&a, &b, &m) == -1 && m.mixed, "like sub-models mix");
  const double *n = m.coeffs[GRIDDEM_AXIS_NORMAL];
  CHECK_CLOSE(n[0], 1.0 / ((1 - 0.09) / 1e6 + (1 - 0.04) / 4e6), 1e-15, 0.0); /* E_eff */
  CHECK_CLOSE(n[1], 10.0, 1e-15, 0.0);                                       /* geometric */
  CHECK(m.coeffs[GRIDDEM_AXIS_TANGENTIAL][0] == GRIDDEM_NULL_COEFF, "k NULL on one side stays NULL");
  CHECK_CLOSE(m.coeffs[GRIDDEM_AXIS_ROLLING][0], 200.0, 1e-15, 0.0);
  /* a mixed material is already effective: k = 4/3 E_eff, not mixed again */
  griddem_pair_params p;
  char why[256];
  CHECK(griddem_spec_to_params(&m, &p, why, sizeof(why)) == 0, "mixed spec converts: %s", why);
  CHECK_CLOSE(p.normal.k, 4.0 / 3.0 * n[0], 1e-15, 0.0);
  spec_from_text("hertz 1e6 20 tangential linear_history 1 1 1", &b);
  CHECK(griddem_spec_mix(&a, &b, &m) == GRIDDEM_AXIS_NORMAL, "different normal models do not mix");
}

static void refusals(void)
{
  static const char *const bad[][2] = {
      {"jkr 1e6 20 0.3 10 tangential linear_history 1 1 1 limit_damping", "limit_damping"},
      {"dmt 1e6 20 0.3 10 damping tsuji tangential linear_history 1 1 1", "tsuji"},
      {"jkr 1e6 20 0.3 10 damping coeff_restitution tangential linear_history 1 1 1", "coeff_restitution"},
      {"hertz 1e6 20 tangential mindlin NULL 0.5 0.4", "mindlin"},
      {"hooke 1e4 20 tangential linear_history 0 0.5 0.4", "linear_history"},
      {"hooke 1e4 20 tangential mindlin 0 0.5 0.4", "mindlin"},
      {"hooke 1e4 20 tangential linear_nohistory 0.5 0.4 twisting marshall", "marshall"},
      {"hooke 1e4 20 tangential linear_history 1 1 1 twisting sds 0 1 0.5", "twisting sds"},
      {"hooke 1e4 20", "tangential"},
  };
  for (size_t k = 0; k < sizeof(bad) / sizeof(bad[0]); k++) {
    griddem_pair_spec s;
    griddem_pair_params p;
    char why[256] = "";
    CHECK(spec_from_text(bad[k][0], &s) == 0, "'%s' reads", bad[k][0]);
    CHECK(griddem_spec_to_params(&s, &p, why, sizeof(why)) != 0 && strstr(why, bad[k][1]),
          "'%s' refused naming %s: '%s'", bad[k][0], bad[k][1], why);
  }
}

static void layout(void)
{
  griddem_pair_spec s;
  double parity[GRIDDEM_MAX_HISTORY];
  spec_from_text("jkr 1e6 20 0.3 10 tangential mindlin_rescale NULL 0.5 0.4 rolling sds 1 1 1 twisting sds 1 1 1", &s);
  const int n = griddem_spec_history(&s, parity);
  CHECK(n == 8, "mindlin_rescale 4 + rolling 3 + twisting 1 values: %d", n);
  const double want[8] = {-1, -1, -1, 1, 1, 1, 1, 1};
  for (int k = 0; k < 8; k++) CHECK(parity[k] == want[k], "parity of value %d", k);
  CHECK(griddem_spec_beyond_contact(&s), "jkr acts beyond contact");
  const griddem_pair_params p = law_from_text("jkr 1e6 20 0.3 10 tangential mindlin_rescale NULL 0.5 0.4 rolling sds 1 1 1 twisting sds 1 1 1");
  CHECK(p.hist_rolling == 4 && p.hist_twisting == 7, "offsets %d %d", p.hist_rolling, p.hist_twisting);
  spec_from_text("hooke 1e4 20 tangential linear_nohistory 1 1", &s);
  CHECK(griddem_spec_history(&s, NULL) == 0 && !griddem_spec_beyond_contact(&s), "no history kept");
  CHECK(griddem_submodel_find(GRIDDEM_AXIS_TANGENTIAL, "mindlin_bogus") == NULL, "unknown names are not found");
  CHECK(griddem_submodel_find(GRIDDEM_AXIS_TWISTING, "sds") != griddem_submodel_find(GRIDDEM_AXIS_ROLLING, "sds"),
        "a name is looked up on its own axis");
}

/* The rows' examples: each of a row's two lines reads and converts, names the row, and names
 * the same sub-models as the other (so the unlike pair mixes and converts too); together they
 * name every row, so the tests that run the examples cover the table. */
static void examples(void)
{
  size_t nrows = 0;
  while (griddem_submodel_at(nrows)) nrows++;
  int shown[64] = {0};
  CHECK(nrows <= sizeof(shown) / sizeof(shown[0]), "%zu rows", nrows);
  for (size_t k = 0; k < nrows; k++) {
    const griddem_submodel *row = griddem_submodel_at(k);
    if (!row->example[0]) {
      CHECK(!row->example[1], "%s %s: both types' examples or neither", griddem_axis_name(row->axis), row->name);
      continue;
    }
    griddem_pair_spec s[2], mixed;
    griddem_pair_params p;
    char why[256] = "";
    for (int type = 0; type < 2; type++) {
      const char *text = row->example[type];
      CHECK(text && spec_from_text(text, &s[type]) == 0, "example '%s' reads", text ? text : "(none)");
      CHECK(griddem_spec_to_params(&s[type], &p, why, sizeof(why)) == 0, "example '%s' converts: %s", text, why);
      CHECK(s[type].sub[row->axis] == row, "example '%s' names %s %s", text, griddem_axis_name(row->axis), row->name);
      for (int axis = 0; axis < GRIDDEM_NAXES; axis++)
        for (size_t r = 0; r < nrows && r < sizeof(shown) / sizeof(shown[0]); r++)
          if (s[type].sub[axis] == griddem_submodel_at(r)) shown[r] = 1;
    }
    CHECK(griddem_spec_mix(&s[0], &s[1], &mixed) == -1 && griddem_spec_to_params(&mixed, &p, why, sizeof(why)) == 0,
          "example of %s %s: the unlike pair mixes and converts: %s", griddem_axis_name(row->axis), row->name, why);
  }
  for (size_t r = 0; r < nrows && r < sizeof(shown) / sizeof(shown[0]); r++)
    CHECK(shown[r], "%s %s is in some row's example", griddem_axis_name(griddem_submodel_at(r)->axis),
          griddem_submodel_at(r)->name);
}

/* pair granular's models that the table lacks are not found on their axis */
static void stock_only(void)
{
  size_t n = 0;
  for (; griddem_stock_only_at(n); n++) {
    const griddem_stock_only *u = griddem_stock_only_at(n);
    int axis = 0;
    while (axis < GRIDDEM_NAXES && strcmp(griddem_axis_name(axis), u->keyword) != 0) axis++;
    const griddem_submodel *m = axis < GRIDDEM_NAXES ? griddem_submodel_find(axis, u->name) : NULL;
    CHECK(!m || (m->flags & GRIDDEM_SUBMODEL_INTERNAL), "%s %s is refused, not a row the style takes", u->keyword, u->name);
  }
  CHECK(n > 0, "pair granular's models the table lacks are listed");
}

int main(void)
{
  examples();
  stock_only();
  conversions();
  mixing();
  refusals();
  layout();
  return check_summary();
}
