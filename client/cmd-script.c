/*
 * `visctl script`: runs visctl's live commands, one a line, on one connection, so that windows
 * created by one line are there for the next. The first failure stops the script, its message
 * starting with FILE:LINE.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "live.h"
#include "visctl.h"

/* The most words a line may have; no command takes nearly as many. */
#define SCRIPT_MAX_WORDS 256

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

/* Runs one line's command on the script's connection; l->where already names the line. */
static int run_line(struct live *l, char *line)
{
	char *words[SCRIPT_MAX_WORDS + 1];
	int n = split(line, words, SCRIPT_MAX_WORDS);
	if (n < 0)
		return line_error(l, "%s", "too many words");
	if (n == 0)
		return VISCTL_EXIT_OK;
	words[n] = NULL;
	const struct visctl_command *cmd = visctl_command_find(words[0]);
	if (words[0][0] == '-')
		return line_error(l, "global options such as '%s' cannot be given in a script",
				  words[0]);
	if (!cmd)
		return line_error(l, "unknown command '%s'", words[0]);
	if (!cmd->live || cmd->live == cmd_script)
		return line_error(l, "'%s' cannot be used in a script", words[0]);
	int ret = cmd->live(l, n, words);
	fflush(stdout);
	return ret;
}

int cmd_script(struct live *l, int argc, char **argv)
{
	if (argc == 2 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)) {
		printf("usage: visctl script FILE|-\n"
		       "  Runs visctl commands, one a line, on one connection: no 'visctl' word and\n"
		       "  no global options; '#' starts a comment. The first failure stops it.\n");
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
		live_error(l, "%s: cannot read: %s", shown, strerror(saved));
		return saved == ENOMEM ? VISCTL_EXIT_FAILURE : VISCTL_EXIT_USAGE;
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
	int ret = VISCTL_EXIT_OK;
	size_t line = 0;
	for (char *p = text, *end = text + len; p < end && ret == VISCTL_EXIT_OK;) {
		char *nl = memchr(p, '\n', (size_t)(end - p));
		char *next = nl ? nl + 1 : end;
		if (nl)
			*nl = '\0';
		snprintf(where, where_len, "%s:%zu", shown, ++line);
		ret = run_line(l, p);
		p = next;
	}
	l->where = outer;
	l->in_script = false;
	free(where);
	free(text);
	return ret;
}
