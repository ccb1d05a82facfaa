/*
 * `visctl script`: runs visctl's live commands, one a line, on one connection, so that windows
 * created by one line are there for the next. The first failure stops the script, its message
 * starting with FILE:LINE. Two things exist only in scripts: `@N` stands for the ID of the window
 * the script's N-th create made (so a script can name its own windows on any daemon), and
 * `batch-begin` … `batch-commit` hold the changes between them for one recompute.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "live.h"
#include "visctl.h"

/* The most words a line may have; no command takes nearly as many. */
#define SCRIPT_MAX_WORDS 256

/* What a script remembers from line to line: its windows, and the batch it is in. */
struct script {
	uint32_t *created; /* created[N - 1]: the window of the N-th create, for @N */
	size_t n_created, cap_created;
	size_t batch_line;  /* the line of the open batch-begin */
	uint32_t batch_seq; /* its request number */
};

/* Splits a line (already NUL-terminated) into words in place, dropping a '#' comment. */
static int split(char *line, char **words, int max)
{
	int n = 0;
	char *p = line;
	char *hash = strchr(line, '#');
	if (hash)
		*hash = '\0';
	for (;;) {
		while (*p == ' ' || *p == '\t' || *p == '\r')
			p++;
		if (!*p)
			return n;
		if (n == max)
			return -1;
		words[n++] = p;
		while (*p && *p != ' ' && *p != '\t' && *p != '\r')
			p++;
		if (*p)
			*p++ = '\0';
	}
}

/* Says what is wrong with a line, prefixed by FILE:LINE; returns the usage exit status. */
static int line_error(struct live *l, const char *fmt, const char *arg)
{
	fprintf(stderr, "%s: ", l->where);
	fprintf(stderr, fmt, arg);
	fputc('\n', stderr);
	return VISCTL_EXIT_USAGE;
}

/* Replaces each @N word by the ID of the script's N-th window; formatted IDs go into ids. */
static int resolve(struct live *l, const struct script *sc, char **words, int n,
		   char ids[][12])
{
	for (int i = 0; i < n; i++) {
		uint32_t k;
		if (words[i][0] != '@')
			continue;
		if (live_parse_u32(words[i] + 1, &k) < 0 || k == 0 || k > sc->n_created) {
			fprintf(stderr, "%s: '%s': the script has created %zu windows so far\n",
				l->where, words[i], sc->n_created);
			return -1;
		}
		snprintf(ids[i], sizeof(ids[i]), "%u", sc->created[k - 1]);
		words[i] = ids[i];
	}
	return 0;
}

/*
 * After a failure: names the retained windows the script made that are still there, which outlive
 * it (the others go with its connection), so that a half-run script leaves nothing unsaid.
 */
static void report_leftovers(struct live *l, const struct script *sc, const char *shown)
{
	struct vis_window_info *w;
	size_t n, kept = 0;
	if (!sc->n_created || !l->client || l->in_batch ||
	    vis_client_get_tree(l->client, &w, &n) < 0)
		return;
	for (size_t i = 0; i < n; i++)
		for (size_t k = 0; k < sc->n_created; k++)
			if (w[i].window == sc->created[k] && (w[i].flags & VIS_WINDOW_RETAINED)) {
				if (!kept++)
					fprintf(stderr, "%s: the retained windows it made stay:", shown);
				fprintf(stderr, " @%zu=%u", k + 1, w[i].window);
			}
	if (kept)
		fputc('\n', stderr);
	free(w);
}

/* Whether a command may stand inside a batch: the changes, which have no reply to wait for. */
static int batchable(const char *name)
{
	static const char *const names[] = { "destroy", "map",	 "unmap", "move",  "resize",
					     "raise",	"lower", "stack", "shape", "opaque" };
	for (size_t i = 0; i < sizeof(names) / sizeof(names[0]); i++)
		if (strcmp(name, names[i]) == 0)
			return 1;
	return 0;
}

/* Runs batch-begin or batch-commit (no arguments); the daemon's verdict comes at the commit. */
static int run_batch(struct live *l, struct script *sc, size_t line, int n, char **words)
{
	int begin = strcmp(words[0], "batch-begin") == 0;
	if (n != 1)
		return line_error(l, "unexpected argument '%s'", words[1]);
	if (begin == l->in_batch)
		return line_error(l, begin ? "%s inside a batch" : "%s without batch-begin",
				  words[0]);
	if (!live_connect(l))
		return VISCTL_EXIT_FAILURE;
	if (begin) {
		if (!(sc->batch_seq = vis_client_batch_begin(l->client)))
			return live_failed(l, words[0]);
		sc->batch_line = line;
		l->in_batch = true;
		return VISCTL_EXIT_OK;
	}
	l->in_batch = false;
	struct vis_error e;
	if (!vis_client_batch_commit(l->client) || vis_client_roundtrip(l->client) < 0)
		return live_failed(l, words[0]);
	if (vis_client_last_error(l->client, &e) && e.seq >= sc->batch_seq)
		return live_error(l, "batch from line %zu: %s: %s: %s", sc->batch_line,
				  vis_request_name(e.opcode), vis_error_code_name(e.code), e.message);
	return VISCTL_EXIT_OK;
}

/* Runs one line's command on the script's connection; l->where already names the line. */
static int run_line(struct live *l, struct script *sc, size_t line, char *text)
{
	char *words[SCRIPT_MAX_WORDS + 1];
	char ids[SCRIPT_MAX_WORDS][12];
	int n = split(text, words, SCRIPT_MAX_WORDS);
	if (n < 0)
		return line_error(l, "%s", "too many words");
	if (n == 0)
		return VISCTL_EXIT_OK;
	words[n] = NULL;
	if (resolve(l, sc, words, n, ids) < 0)
		return VISCTL_EXIT_USAGE;
	if (strcmp(words[0], "batch-begin") == 0 || strcmp(words[0], "batch-commit") == 0)
		return run_batch(l, sc, line, n, words);
	const struct visctl_command *cmd = visctl_command_find(words[0]);
	if (words[0][0] == '-')
		return line_error(l, "global options such as '%s' cannot be given in a script",
				  words[0]);
	if (!cmd)
		return line_error(l, "unknown command '%s'", words[0]);
	if (!cmd->live || cmd->live == cmd_script || cmd->live == cmd_stress)
		return line_error(l, "'%s' cannot be used in a script", words[0]);
	if (l->in_batch && !batchable(words[0]))
		return line_error(l, "'%s' cannot be used inside a batch: only changes can", words[0]);
	l->created = 0;
	int ret = cmd->live(l, n, words);
	fflush(stdout);
	if (ret == VISCTL_EXIT_OK && l->created) {
		if (sc->n_created == sc->cap_created) {
			size_t cap = sc->cap_created ? 2 * sc->cap_created : 64;
			uint32_t *more = realloc(sc->created, cap * sizeof(*more));
			if (!more)
				return live_error(l, "script: %s", strerror(ENOMEM));
			sc->created = more;
			sc->cap_created = cap;
		}
		sc->created[sc->n_created++] = l->created;
	}
	return ret;
}

int cmd_script(struct live *l, int argc, char **argv)
{
	if (argc == 2 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)) {
		printf("usage: visctl script FILE|-\n"
		       "  Runs visctl commands, one a line, on one connection: no 'visctl' word and\n"
		       "  no global options; '#' starts a comment. The first failure stops it.\n"
		       "  @N stands for the window the script's N-th create made; changes between\n"
		       "  batch-begin and batch-commit lines are applied together.\n");
		return fflush(stdout) == 0 ? VISCTL_EXIT_OK : VISCTL_EXIT_FAILURE;
	}
	if (argc != 2)
		return live_usage(l, argv[0], "expected FILE|-, got %d arguments", argc - 1);
	const char *path = argv[1];
	const char *shown = strcmp(path, "-") == 0 ? "<stdin>" : path;
	char *text;
	size_t len;
	if (visctl_read_all(path, &text, &len) < 0) {
		int saved = errno;
		/* Not bad usage: the file is missing or unreadable now, a runtime error. */
		return live_error(l, "%s: cannot read: %s", shown, strerror(saved));
	}
	if (memchr(text, '\0', len)) {
		free(text);
		return live_usage(l, argv[0], "%s: NUL byte in the script", shown);
	}
	/* Room for a NUL after the last line, which may lack its newline. */
	char *grown = realloc(text, len + 1);
	if (!grown) {
		free(text);
		return live_error(l, "script: %s", strerror(ENOMEM));
	}
	text = grown;
	text[len] = '\0';

	size_t where_len = strlen(shown) + 24;
	char *where = malloc(where_len);
	if (!where) {
		free(text);
		return live_error(l, "script: %s", strerror(ENOMEM));
	}
	const char *outer = l->where;
	l->where = where;
	l->in_script = true;
	struct script sc = { 0 };
	int ret = VISCTL_EXIT_OK;
	size_t line = 0;
	for (char *p = text, *end = text + len; p < end && ret == VISCTL_EXIT_OK;) {
		char *nl = memchr(p, '\n', (size_t)(end - p));
		char *next = nl ? nl + 1 : end;
		if (nl)
			*nl = '\0';
		snprintf(where, where_len, "%s:%zu", shown, ++line);
		ret = run_line(l, &sc, line, p);
		p = next;
	}
	if (ret == VISCTL_EXIT_OK && l->in_batch) {
		snprintf(where, where_len, "%s:%zu", shown, sc.batch_line);
		ret = line_error(l, "%s without batch-commit", "batch-begin");
	}
	l->where = outer;
	if (ret != VISCTL_EXIT_OK)
		report_leftovers(l, &sc, shown);
	l->in_script = false;
	l->in_batch = false;
	free(sc.created);
	free(where);
	free(text);
	return ret;
}
