/*
 * Replays a libFuzzer target's corpus without libFuzzer, in the ordinary build and its sanitizer
 * pass: every file of the directories (or the files) given as arguments goes once through
 * LLVMFuzzerTestOneInput, in name order. Each file's name is printed before it runs, so that the
 * log names the input of a failed check. A directory without files is an error: a corpus that
 * went missing must not pass as an empty one.
 */
#include <dirent.h>
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Runs the target on one file's bytes, in a buffer of exactly its size. Returns 0 or -1. */
static int replay_file(const char *path)
{
	FILE *fp = fopen(path, "rb");
	struct stat st;
	if (!fp || fstat(fileno(fp), &st) < 0) {
		fprintf(stderr, "replay: %s: %s\n", path, strerror(errno));
		if (fp)
			fclose(fp);
		return -1;
	}
	size_t len = (size_t)st.st_size;
	/* Exactly len bytes, so that the sanitizers see a read past the end. */
	uint8_t *data = malloc(len ? len : 1);
	int ok = data && fread(data, 1, len, fp) == len;
	fclose(fp);
	if (!ok) {
		fprintf(stderr, "replay: %s: cannot read it\n", path);
		free(data);
		return -1;
	}
	printf("replay: %s (%zu bytes)\n", path, len);
	fflush(stdout);
	LLVMFuzzerTestOneInput(data, len);
	free(data);
	return 0;
}

static int compare_names(const void *a, const void *b)
{
	return strcmp(*(char *const *)a, *(char *const *)b);
}

/* Replays every regular file of a directory. Returns how many, or -1. */
static long replay_dir(const char *dir)
{
	DIR *d = opendir(dir);
	if (!d) {
		fprintf(stderr, "replay: %s: %s\n", dir, strerror(errno));
		return -1;
	}
	char **names = NULL;
	size_t n = 0, cap = 0;
	struct dirent *e;
	while ((e = readdir(d))) {
		if (e->d_name[0] == '.')
			continue;
		if (n == cap) {
			cap = cap ? cap * 2 : 256;
			char **p = realloc(names, cap * sizeof(*names));
			if (!p)
				break;
			names = p;
		}
		size_t len = strlen(dir) + strlen(e->d_name) + 2;
		if (!(names[n] = malloc(len)))
			break;
		snprintf(names[n++], len, "%s/%s", dir, e->d_name);
	}
	closedir(d);
	qsort(names, n, sizeof(*names), compare_names);
	long count = 0;
	for (size_t i = 0; i < n; i++) {
		struct stat st;
		if (count >= 0 && stat(names[i], &st) == 0 && S_ISREG(st.st_mode))
			count = replay_file(names[i]) < 0 ? -1 : count + 1;
		free(names[i]);
	}
	free(names);
	if (count == 0)
		fprintf(stderr, "replay: %s: no files\n", dir);
	return count > 0 ? count : -1;
}

int main(int argc, char **argv)
{
	long total = 0;
	if (argc < 2) {
		fprintf(stderr, "usage: %s DIR|FILE...\n", argv[0]);
		return 2;
	}
	for (int i = 1; i < argc; i++) {
		struct stat st;
		long n;
		if (stat(argv[i], &st) == 0 && S_ISDIR(st.st_mode))
			n = replay_dir(argv[i]);
		else
			n = replay_file(argv[i]) < 0 ? -1 : 1;
		if (n < 0)
			return 1;
		total += n;
	}
	printf("replay: %ld inputs, no failure\n", total);
	return 0;
}
