/* firmament serve: renders maps on request for a long-running client such as the Blender add-on's
 * live sky.  One JSON request per line on standard input, one JSON reply per request on standard
 * output; the protocol is in docs/cli.md ("firmament serve"). */
#ifndef FM_CLI_SERVE_H
#define FM_CLI_SERVE_H

/* argv[0] is "serve"; returns the exit code: 0 at the end of the input, 2 for bad options,
 * 128 + N when signal N stopped it. */
int run_serve(int argc, char **argv);

#endif
