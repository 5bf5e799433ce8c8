/* GRIDDEM reduced-order model file: reading and checking (griddem_rom_model.h). */
#include "griddem_rom_model.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* a word of the file: its bytes (NUL-terminated in the parser's copy of the text) and its line */
typedef struct model_word {
  char *text;
  size_t len;
  int line;
} model_word;

typedef struct model_parser {
  const char *name;
  model_word *words;
  size_t nwords;
  int nlines;
  size_t p;    /* the next word */
  double version;
  char *message;
  size_t message_size;
  int failed;
} model_parser;

/* a word as a message shows it: bytes other than printable ASCII as \xNN (a binary file's words
 * hold NUL bytes, which would end the message), at most SHOWN_BYTES of it */
#define SHOWN_BYTES 40
#define SHOWN_SIZE (4 * SHOWN_BYTES + 4)
static const char *shown(const model_word *w, char out[SHOWN_SIZE])
{
  char *o = out;
  for (size_t k = 0; k < w->len && k < SHOWN_BYTES; k++) {
    const unsigned char c = (unsigned char) w->text[k];
    if (c >= 0x20 && c < 0x7f) *o++ = (char) c;
    else o += sprintf(o, "\\x%02x", (unsigned) c);
  }
  strcpy(o, w->len > SHOWN_BYTES ? "..." : "");
  return out;
}

/* what the parser found at word k: the word quoted, or the end of the file */
#define FOUND_SIZE (SHOWN_SIZE + 2)
static const char *found(const model_parser *ps, size_t k, char out[FOUND_SIZE])
{
  char s[SHOWN_SIZE];
  if (k < ps->nwords) snprintf(out, FOUND_SIZE, "'%s'", shown(&ps->words[k], s));
  else snprintf(out, FOUND_SIZE, "the end of the file");
  return out;
}

/* x as the messages write a number, the way LAMMPS's fmt writes a double with "{}": the shortest
 * digits that read back as x, in fixed notation for decimal exponents -4 to 15, else as
 * d.ddde+XX (nan and inf, which no accepted word holds, as fmt writes them) */
#define NUMBER_SIZE 64
static const char *number_text(double x, char out[NUMBER_SIZE])
{
  if (!isfinite(x)) {
    snprintf(out, NUMBER_SIZE, "%s", isnan(x) ? "nan" : x < 0 ? "-inf" : "inf");
    return out;
  }
  char e[NUMBER_SIZE];
  for (int ndigit = 1;; ndigit++) {
    snprintf(e, sizeof e, "%.*e", ndigit - 1, x);
    if (ndigit == 17 || strtod(e, NULL) == x) break;
  }
  /* e: [-]d[.ddd]e(+|-)XX; digits without the point and trailing zeros */
  const char *m = e[0] == '-' ? e + 1 : e, *mark = strchr(e, 'e');
  const int exponent = atoi(mark + 1);
  char digits[24];    /* at most 17 */
  int n = 0;
  for (const char *c = m; c < mark; c++)
    if (*c != '.') digits[n++] = *c;
  while (n > 1 && digits[n - 1] == '0') n--;
  digits[n] = '\0';
  char *o = out + sprintf(out, "%s", e[0] == '-' ? "-" : "");
  if (exponent < -4 || exponent >= 16)
    sprintf(o, "%c%s%se%c%02d", digits[0], n > 1 ? "." : "", digits + 1, exponent < 0 ? '-' : '+', abs(exponent));
  else if (exponent >= n - 1)
    sprintf(o, "%s%.*s", digits, exponent - (n - 1), "000000000000000");
  else if (exponent >= 0)
    sprintf(o, "%.*s.%s", exponent + 1, digits, digits + exponent + 1);
  else
    sprintf(o, "0.%.*s%s", -exponent - 1, "000", digits);
  return out;
}

/* The first error: where it is (word k's line, or the end of the file) and what is wrong. */
#define WHAT_SIZE (GRIDDEM_ROM_MODEL_MESSAGE - 64)
static void fail(model_parser *ps, size_t k, const char *format, ...)
{
  if (ps->failed) return;
  ps->failed = 1;
  char what[WHAT_SIZE];
  va_list args;
  va_start(args, format);
  vsnprintf(what, sizeof what, format, args);
  va_end(args);
  if (k < ps->nwords)
    snprintf(ps->message, ps->message_size, "model file %s, line %d: %s", ps->name, ps->words[k].line, what);
  else if (ps->nwords == 0)
    snprintf(ps->message, ps->message_size, "model file %s holds no words: %s", ps->name, what);
  else
    snprintf(ps->message, ps->message_size, "model file %s, at its end (line %d): %s", ps->name, ps->nlines, what);
}

static int word_is(const model_word *w, const char *text)
{
  return w->len == strlen(text) && memcmp(w->text, text, w->len) == 0;
}

/* the whole word is a finite number (a NUL byte inside it is not part of one) */
static int finite_number(const model_word *w, double *out)
{
  char *end = NULL;
  *out = strtod(w->text, &end);
  return w->len > 0 && end == w->text + w->len && isfinite(*out);
}

/* a line 'key values...': the key, and nvalues words after it */
static int expect(model_parser *ps, const char *key, const char *values, int nvalues)
{
  if (ps->failed) return 0;
  if (ps->p >= ps->nwords || !word_is(&ps->words[ps->p], key)) {
    char f[FOUND_SIZE];
    fail(ps, ps->p, "expected '%s %s', found %s", key, values, found(ps, ps->p, f));
    return 0;
  }
  if (ps->p + nvalues >= ps->nwords) {
    fail(ps, ps->p, "'%s' needs %d values (%s), found the end of the file", key, nvalues, values);
    return 0;
  }
  ps->p++;
  return 1;
}

/* the next word as a finite number (expect has made sure there is one) */
static void number(model_parser *ps, double *out, const char *what)
{
  if (ps->failed) return;
  char s[SHOWN_SIZE];
  if (!finite_number(&ps->words[ps->p], out))
    fail(ps, ps->p, "expected %s (a finite number), found '%s'", what, shown(&ps->words[ps->p], s));
  ps->p++;
}

/* an optional line of format version `version` or later, named by its first word */
static int optional(model_parser *ps, const char *key, int version)
{
  if (ps->failed || ps->p >= ps->nwords || !word_is(&ps->words[ps->p], key)) return 0;
  if (ps->version < version)
    fail(ps, ps->p, "'%s' needs format version %d (the file has version %g)", key, version, ps->version);
  return !ps->failed;
}

/* the nrow x ncol numbers of a block that starts at the next word (its header line at word
 * header), into *out (allocated here) */
static void block(model_parser *ps, double **out, size_t header, double nrow, double ncol)
{
  if (ps->failed) return;
  const model_word *h = &ps->words[header];
  const size_t left = ps->nwords - ps->p;
  char r[NUMBER_SIZE], c[NUMBER_SIZE], rc[NUMBER_SIZE], s[SHOWN_SIZE];
  number_text(nrow, r);
  number_text(ncol, c);
  if ((double) left < nrow * ncol) {
    fail(ps, ps->nwords, "'%s %s %s' (line %d) needs %s x %s = %s values, found %zu", h->text, r, c, h->line, r, c,
         number_text(nrow * ncol, rc), left);
    return;
  }
  const size_t n = (size_t) (nrow * ncol);
  if (!(*out = malloc(n * sizeof(double)))) {
    fail(ps, header, "no memory for the %s x %s values of '%s'", r, c, h->text);
    return;
  }
  for (size_t k = 0; k < n && !ps->failed; k++, ps->p++)
    if (!finite_number(&ps->words[ps->p], &(*out)[k]))
      fail(ps, ps->p, "expected value %zu of row %zu of '%s' (a finite number), found '%s'", k % (size_t) ncol + 1,
           k / (size_t) ncol + 1, h->text, shown(&ps->words[ps->p], s));
}

static int is_blank(char c)
{
  return c == ' ' || c == '\t' || c == '\v' || c == '\f' || c == '\r';
}

/* The words of text (len bytes, text[len] = '\0'), each NUL-terminated in place, and the number
 * of lines (a last line without a newline counts). Returns 0, or -1 without memory. */
static int split_words(char *text, size_t len, model_parser *ps)
{
  size_t capacity = 0;
  int line = 1;
  ps->nlines = len > 0 && text[len - 1] != '\n';
  for (size_t i = 0; i < len;) {
    if (text[i] == '\n') {
      line++;
      i++;
    } else if (text[i] == '#') {
      while (i < len && text[i] != '\n') i++;
    } else if (is_blank(text[i])) {
      i++;
    } else {
      const size_t start = i;
      while (i < len && text[i] != '\n' && text[i] != '#' && !is_blank(text[i])) i++;
      if (ps->nwords == capacity) {
        capacity = capacity ? 2 * capacity : 1024;
        model_word *grown = realloc(ps->words, capacity * sizeof(model_word));
        if (!grown) return -1;
        ps->words = grown;
      }
      ps->words[ps->nwords++] = (model_word){text + start, i - start, line};
      /* the word's end, now its NUL: a blank, a newline or a comment's start */
      if (i < len) {
        const char end = text[i];
        text[i++] = '\0';
        if (end == '\n') line++;
        else if (end == '#')
          while (i < len && text[i] != '\n') i++;
      }
    }
  }
  ps->nlines += line - 1;
  return 0;
}

/* The file's lines in order, each checked as it comes (griddem_rom_model.h). */
static void parse_words(model_parser *ps, griddem_rom_model *model)
{
  double n[3] = {0.0, 0.0, 0.0}, box[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0}, controls = 0.0, lambda = 0.0;
  char a[NUMBER_SIZE], b[NUMBER_SIZE], c[NUMBER_SIZE], d[NUMBER_SIZE], e[NUMBER_SIZE], f[NUMBER_SIZE],
      g[NUMBER_SIZE], h[NUMBER_SIZE], s[SHOWN_SIZE];
  size_t at = ps->p;
  if (expect(ps, "griddem/rom", "VERSION", 1)) {
    number(ps, &ps->version, "the format version");
    if (!ps->failed && (ps->version < 1 || ps->version > GRIDDEM_ROM_VERSION || ps->version != floor(ps->version)))
      fail(ps, at, "format version %s is not supported (this build reads versions 1 to %d)",
           shown(&ps->words[ps->p - 1], s), GRIDDEM_ROM_VERSION);
  }
  at = ps->p;
  if (expect(ps, "grid", "NX NY NZ", 3))
    for (int k = 0; k < 3; k++) number(ps, &n[k], "a number of voxels");
  for (int k = 0; k < 3 && !ps->failed; k++)
    if (n[k] < 1 || n[k] != floor(n[k]) || n[k] > 1e4)
      fail(ps, at, "grid size %s %s %s must be positive integers", number_text(n[0], a), number_text(n[1], b),
           number_text(n[2], c));
  at = ps->p;
  if (expect(ps, "box", "XLO XHI YLO YHI ZLO ZHI", 6))
    for (int k = 0; k < 6; k++) number(ps, &box[k], "a box bound");
  for (int k = 0; k < 3 && !ps->failed; k++)
    if (!(box[2 * k + 1] > box[2 * k])) fail(ps, at, "box bounds along axis %c are not increasing", "xyz"[k]);
  if (optional(ps, "frame", 2) && expect(ps, "frame", "moving", 1)) {
    if (!word_is(&ps->words[ps->p], "moving"))
      fail(ps, ps->p, "expected 'frame moving' (the only frame), found '%s'", shown(&ps->words[ps->p], s));
    ps->p++;
    model->moving = 1;
  }
  at = ps->p;
  if (expect(ps, "controls", "NC", 1)) number(ps, &controls, "the number of controls");
  if (!ps->failed && (controls < 0 || controls != floor(controls)))
    fail(ps, at, "number of controls %s is not a count", number_text(controls, a));
  if (expect(ps, "lambda", "L", 1)) number(ps, &lambda, "the ridge parameter");
  if (optional(ps, "form", 3) && expect(ps, "form", "linear|occupancy", 1)) {
    if (word_is(&ps->words[ps->p], "occupancy"))
      model->form = GRIDDEM_ROM_OCCUPANCY;
    else if (!word_is(&ps->words[ps->p], "linear"))
      fail(ps, ps->p, "expected 'form linear' or 'form occupancy', found '%s'", shown(&ps->words[ps->p], s));
    ps->p++;
  }
  const int occupancy = model->form == GRIDDEM_ROM_OCCUPANCY;
  double nrow = 0.0, ncol = 0.0;
  const size_t weights_at = ps->p;
  if (expect(ps, "weights", "NROW NCOL", 2)) {
    number(ps, &nrow, "the number of rows");
    number(ps, &ncol, "the number of columns");
  }
  const double nvox = n[0] * n[1] * n[2];
  number_text(n[0], a);
  number_text(n[1], b);
  number_text(n[2], c);
  number_text(nvox, d);
  number_text(nrow, e);
  number_text(ncol, f);
  if (!ps->failed && nrow != 3 * nvox)
    fail(ps, weights_at, "weights has %s rows; grid size %s %s %s needs 3 x %s = %s", e, a, b, c, d,
         number_text(3 * nvox, g));
  if (!ps->failed && occupancy && ncol != 1 + controls)
    fail(ps, weights_at, "weights has %s columns; form occupancy with %s controls needs 1 + %s = %s", f,
         number_text(controls, g), g, number_text(1 + controls, h));
  if (!ps->failed && !occupancy && ncol != 1 + nvox + controls)
    fail(ps, weights_at, "weights has %s columns; grid size %s %s %s and %s controls need 1 + %s + %s = %s", f, a, b, c,
         number_text(controls, g), d, g, number_text(1 + nvox + controls, h));
  block(ps, &model->weights, weights_at, nrow, ncol);
  if (!ps->failed && ps->p < ps->nwords) {
    if (!word_is(&ps->words[ps->p], "force")) {
      char force[NUMBER_SIZE + 32] = "";
      if (ps->version >= 2) snprintf(force, sizeof force, " or a block 'force 3 %s'", f);
      fail(ps, ps->p, "expected the end of the file%s after the %s x %s weights, found '%s'", force, e, f,
           shown(&ps->words[ps->p], s));
    }
    const size_t force_at = ps->p;
    double frow = 0.0, fcol = 0.0;
    if (optional(ps, "force", 2) && expect(ps, "force", "3 NCOL", 2)) {
      number(ps, &frow, "the number of rows");
      number(ps, &fcol, "the number of columns");
    }
    if (!ps->failed && (frow != 3 || fcol != ncol))
      fail(ps, force_at, "force has %s rows and %s columns; expected 3 and %s (as weights)", number_text(frow, a),
           number_text(fcol, b), f);
    block(ps, &model->force, force_at, 3, ncol);
    if (!ps->failed && ps->p < ps->nwords)
      fail(ps, ps->p, "expected the end of the file after the 3 x %s force values, found '%s'", f,
           shown(&ps->words[ps->p], s));
  }
  model->version = (int) ps->version;
  for (int k = 0; k < 3; k++) {
    model->box.n[k] = (int) n[k];
    model->box.lo[k] = box[2 * k];
    model->box.hi[k] = box[2 * k + 1];
    model->box.periodic[k] = 0;
  }
  model->ncontrol = (int) controls;
  model->lambda = lambda;
}

/* parses text (len bytes, text[len] = '\0'), NUL-terminating its words in place */
static int parse_text(const char *name, char *text, size_t len, griddem_rom_model *model, char *message,
                      size_t message_size)
{
  model_parser ps;
  memset(&ps, 0, sizeof ps);
  ps.name = name;
  ps.message = message;
  ps.message_size = message_size;
  memset(model, 0, sizeof *model);
  if (split_words(text, len, &ps) != 0) {
    snprintf(message, message_size, "no memory for the words of model file %s", name);
    ps.failed = 1;
  } else
    parse_words(&ps, model);
  free(ps.words);
  if (!ps.failed) return 0;
  griddem_rom_model_free(model);
  return -1;
}

int griddem_rom_model_parse(const char *name, const char *text, size_t len, griddem_rom_model *model,
                            char *message, size_t message_size)
{
  char *copy = malloc(len + 1);
  if (!copy) {
    memset(model, 0, sizeof *model);
    snprintf(message, message_size, "no memory to read model file %s (%zu bytes)", name, len);
    return -1;
  }
  memcpy(copy, text, len);
  copy[len] = '\0';
  const int status = parse_text(name, copy, len, model, message, message_size);
  free(copy);
  return status;
}

int griddem_rom_model_read(const char *path, griddem_rom_model *model, char *message, size_t message_size)
{
  memset(model, 0, sizeof *model);
  FILE *in = fopen(path, "rb");
  if (!in) {
    snprintf(message, message_size, "cannot open model file %s", path);
    return -1;
  }
  size_t len = 0, capacity = 1 << 16;
  char *text = malloc(capacity);
  while (text) {
    len += fread(text + len, 1, capacity - 1 - len, in);
    if (len < capacity - 1) break;
    char *grown = realloc(text, 2 * capacity);
    if (!grown) {
      free(text);
      text = NULL;
    } else {
      text = grown;
      capacity *= 2;
    }
  }
  const int unread = ferror(in);
  fclose(in);
  if (!text || unread) {
    snprintf(message, message_size, "cannot read model file %s (%s)", path, text ? "a read error" : "no memory");
    free(text);
    return -1;
  }
  text[len] = '\0';
  const int status = parse_text(path, text, len, model, message, message_size);
  free(text);
  return status;
}

void griddem_rom_model_free(griddem_rom_model *model)
{
  free(model->weights);
  free(model->force);
  memset(model, 0, sizeof *model);
}
