#include "usage.h"

#include "option_table.h"
#include "sun_command.h"

#include <string.h>

enum { WIDTH = 100 }; /* the help's lines end before this column */

const command_usage commands[] = {
    /* the first row: its help begins with every command's usage line */
    {"render", "[options] [-o OUT.exr]", NULL, NULL, option_print_help},
    {"sun",
     "--date YYYY-MM-DD --time HH:MM[:SS] --latitude DEG --longitude DEG [--utc-offset +-HH[:MM]] [--altitude M] "
     "[--refraction on|off] [--pressure MBAR] [--temperature C] [--delta-t S] [--json]",
     NULL, NULL, sun_print_help},
    {"compare", "IMAGE.exr REFERENCE.exr [--exclude-sun DEG] [--json]", NULL,
     "The relative error of IMAGE's luminance against REFERENCE's (the same size), pixel by pixel:\n"
     "its root mean square, 99th percentile, mean (the bias) and largest value, and the mean\n"
     "distance of the CIE xy chromaticities.\n"
     "\n"
     "  --exclude-sun DEG   leave out the pixels within DEG of the reference's sun, [0, 180]\n"
     "                      (default 0: every pixel)\n"
     "  --json              one JSON object on stdout\n",
     NULL},
    {"info", "FILE.exr", "the EXR's header: standard and firmament.* attributes",
     "Prints the header of the EXR's first part, one \"name (type): value\" per line: the standard\n"
     "attributes (channels, compression, chromaticities, ...) first, then firmament.*, each\n"
     "alphabetically.\n",
     NULL},
    {"options", "--json", "render's options as JSON: flags, preset keys, ranges, defaults",
     "Prints the options of `firmament render` as one JSON object: each option's flag, preset key,\n"
     "kind, range and unit, default, choices and help (what the Blender add-on reads).\n",
     NULL},
    {"serve", "[--cache DIR | --no-cache] [--memory N] [--threads N] [--refine N]",
     "a map per JSON request line on standard input, for live clients",
     "Renders a map per request: one JSON object per line on standard input (render options as a\n"
     "sky preset writes them, \"output\", optional \"sidecar\" and \"id\"), one JSON reply per line on\n"
     "standard output.  A request that arrives while another waits replaces it.  docs/cli.md.\n"
     "\n"
     "  --cache DIR   where built atmospheres are kept between runs (default\n"
     "                $XDG_CACHE_HOME/firmament, else ~/.cache/firmament)\n"
     "  --no-cache    keep them in memory only\n"
     "  --memory N    atmospheres kept in memory, 1-64 (default 2)\n"
     "  --threads N   threads per build and render, 0-256 (default 0: one per core)\n"
     "  --refine N    rounds of paths added to the deep twilight tables while idle, 0-64 (default 64:\n"
     "                as many as the library makes; 0: none)\n",
     NULL},
    {"batch", NULL, "many maps from a manifest: docs/batch.md",
     "Many maps as independent, restartable jobs (docs/batch.md): plan writes the jobs into a\n"
     "manifest (JSON Lines, one job per line), run renders some of them, slurm runs them as a Slurm\n"
     "job array, summary gathers their sidecars into a table and a heat map.\n"
     "firmament batch SUBCOMMAND --help: that subcommand's options.\n",
     NULL},
    {"batch plan",
     "-o MANIFEST [--out-dir DIR] [--preset NAME]... [--place NAME,LAT,LON,UTC_OFFSET]... "
     "[--date D | --date-start D --date-end D] [--times HH:MM,... | --time-start T --time-end T --step MIN] "
     "[--sun-above DEG] [--epw FILE] [--set KEY=VALUE]... [--seed N]",
     NULL,
     "Writes a manifest, one job per line: presets x places x dates x times (presets outermost), those\n"
     "with the sun above --sun-above kept.  The manifest is written whole or not at all; its folder\n"
     "and the maps' folder are created where missing.\n"
     "\n"
     "  -o MANIFEST          the manifest to write (JSON Lines)\n"
     "  --out-dir DIR        the maps' folder, relative to the manifest's (default maps)\n"
     "  --preset NAME        a sky preset (or a preset file) for a set of jobs; repeatable\n"
     "  --place NAME,LAT,LON,UTC_OFFSET\n"
     "                       a place, e.g. paris,48.857,2.352,+01:00; repeatable\n"
     "  --date D             one date, YYYY-MM-DD; --date-start D --date-end D: every day between\n"
     "  --times HH:MM,...    local clock times; --time-start T --time-end T --step MIN: a time every\n"
     "                       MIN minutes, [1, 1440]\n"
     "  --sun-above DEG      keep the jobs whose sun is above DEG, [-90, 90] (needs --place, a date\n"
     "                       and times, or --epw; with --epw default 0)\n"
     "  --epw FILE           the place, dates and hours, and each hour's aerosol, albedo and sky\n"
     "                       cover, from an EnergyPlus weather file (not with --place, --date, --times)\n"
     "  --set KEY=VALUE      a preset key for every job, e.g. width=1024; repeatable\n"
     "  --seed N             job i gets the seed N + i, [0, 2^52] (default 0)\n",
     NULL},
    {"batch run", "MANIFEST --index I [--count N] [--skip-existing] [--threads T]", NULL,
     "Renders jobs I to I+N-1 of the manifest through the same code as `firmament render`.  A failed\n"
     "job is reported and the run goes on; the exit code is then that of the first failure.\n"
     "\n"
     "  --index I          the first job, from 0\n"
     "  --count N          how many, [1, 100000000] (default 1; past the end stops at the end)\n"
     "  --skip-existing    skip a job whose map exists and whose sidecar records this very job\n"
     "  --threads T        threads per render, [0, 1024] (default 0: one per core)\n",
     NULL},
    {"batch slurm",
     "MANIFEST [-o SCRIPT] [--jobs-per-task K] [--max-concurrent M] [--partition P] [--time T] "
     "[--cpus-per-task C] [--skip-existing] [--submit]",
     NULL,
     "Writes an sbatch script running the manifest as a Slurm job array: task t runs\n"
     "`firmament batch run MANIFEST --index t*K --count K`, logging beside the script.\n"
     "\n"
     "  -o SCRIPT            the script (default: MANIFEST with .sbatch)\n"
     "  --jobs-per-task K    jobs per array task (default 1)\n"
     "  --max-concurrent M   at most M tasks running at once (default: no limit)\n"
     "  --partition P        #SBATCH --partition\n"
     "  --time T             #SBATCH --time, the tasks' time limit\n"
     "  --cpus-per-task C    cores per task, the renders' threads (default 1)\n"
     "  --skip-existing      the tasks skip the jobs already done (to resubmit after a failure)\n"
     "  --submit             run sbatch --parsable and print the array's id\n",
     NULL},
    {"batch summary", "MANIFEST [-o CSV] [--png PNG]", NULL,
     "Reads the sidecars of the manifest's jobs into a CSV, a row per job (the sun, the illuminances,\n"
     "the AOD and sky cover), and draws the global horizontal illuminance per day of the year and\n"
     "hour as a PNG heat map.\n"
     "\n"
     "  -o CSV      the table (default: MANIFEST with .csv)\n"
     "  --png PNG   the heat map (default: MANIFEST with .png)\n",
     NULL},
};
const int command_count = (int)(sizeof commands / sizeof commands[0]);

/* Whether row c is a subcommand of parent ("batch plan" of "batch"). */
static int is_sub(const command_usage *c, const char *parent)
{
    size_t n = strlen(parent);
    return strncmp(c->name, parent, n) == 0 && c->name[n] == ' ';
}

const command_usage *command_find(const char *name, const char *sub)
{
    for (int i = 0; i < command_count; i++)
        if (strcmp(commands[i].name, name) == 0) {
            for (int j = 0; sub && j < command_count; j++)
                if (is_sub(&commands[j], name) && strcmp(commands[j].name + strlen(name) + 1, sub) == 0)
                    return &commands[j];
            return &commands[i];
        }
    return NULL;
}

int command_help_asked(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0)
            return 1;
    return 0;
}

/* The synopsis, or for a command of subcommands their names: "plan|run|slurm|summary ...". */
static const char *synopsis_of(const command_usage *c, char *buf, size_t size)
{
    if (c->synopsis)
        return c->synopsis;
    size_t used = 0;
    buf[0] = '\0';
    for (int i = 0; i < command_count && used < size; i++)
        if (is_sub(&commands[i], c->name))
            used += (size_t)snprintf(buf + used, size - used, "%s%s", used ? "|" : "",
                                     commands[i].name + strlen(c->name) + 1);
    if (used < size)
        snprintf(buf + used, size - used, " ...");
    return buf;
}

/* lead, "firmament NAME", the synopsis and "(about)", wrapped before WIDTH under the synopsis'
 * start; a bracketed or parenthesized group stays on one line. */
static void print_usage_line(FILE *f, const char *lead, const command_usage *c)
{
    char names[256], about[256] = "";
    const char *syn = synopsis_of(c, names, sizeof names);
    if (c->about)
        snprintf(about, sizeof about, "(%s)", c->about);
    int indent = fprintf(f, "%sfirmament %s ", lead, c->name), column = indent;
    const char *parts[] = {syn, about};
    for (int k = 0; k < 2; k++)
        for (const char *p = parts[k]; *p;) {
            size_t n = 0;
            for (int depth = 0; p[n] && (depth > 0 || p[n] != ' '); n++)
                depth += (p[n] == '[' || p[n] == '(') - (p[n] == ']' || p[n] == ')');
            int gap = column == indent ? 0 : (k == 1 && p == parts[1]) ? 2 : 1; /* two before the about */
            if (gap && column + gap + (int)n >= WIDTH) {
                fprintf(f, "\n%*s", indent, "");
                column = indent;
                gap = 0;
            }
            column += fprintf(f, "%*s%.*s", gap, "", (int)n, p);
            p += n;
            while (*p == ' ')
                p++;
        }
    fputc('\n', f);
}

/* Every command's usage line (render's first), as `firmament --help` begins. */
static void print_overview(FILE *f)
{
    for (int i = 0; i < command_count; i++)
        if (!strchr(commands[i].name, ' '))
            print_usage_line(f, i == 0 ? "usage: " : "       ", &commands[i]);
    fputs("       firmament COMMAND --help   (that command's usage and options)\n"
          "       firmament --help | --version\n",
          f);
}

void command_print_help(FILE *f, const command_usage *c)
{
    if (c == &commands[0]) {
        print_overview(f);
    } else if (!c->synopsis) {
        int first = 1;
        for (int i = 0; i < command_count; i++)
            if (is_sub(&commands[i], c->name)) {
                print_usage_line(f, first ? "usage: " : "       ", &commands[i]);
                first = 0;
            }
    } else {
        print_usage_line(f, "usage: ", c);
    }
    if (c->text)
        fprintf(f, "\n%s", c->text);
    if (c->print_more)
        c->print_more(f);
}

const char *command_usage_line(const char *name)
{
    static char line[1024];
    char names[256];
    const command_usage *c = command_find(name, NULL);
    if (!c)
        return "";
    snprintf(line, sizeof line, "usage: firmament %s %s%s%s%s", c->name, synopsis_of(c, names, sizeof names),
             c->about ? " (" : "", c->about ? c->about : "", c->about ? ")" : "");
    return line;
}
