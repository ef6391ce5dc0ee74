/* firmament sun: the sun's position, distance, sunrise, solar noon and sunset for a date, time and
 * place (fm_solar_position_compute), as text or as one JSON object. */
#include "sun_command.h"

#include "numbers.h"
#include "report.h"
#include "time_args.h"
#include "usage.h"

#include "firmament/firmament.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum {
    SUN_DATE = 256,
    SUN_TIME,
    SUN_UTC_OFFSET,
    SUN_LATITUDE,
    SUN_LONGITUDE,
    SUN_ALTITUDE,
    SUN_REFRACTION,
    SUN_PRESSURE,
    SUN_TEMPERATURE,
    SUN_DELTA_T,
    SUN_JSON,
};

static const struct option sun_options[] = {
    {"date", required_argument, NULL, SUN_DATE},
    {"time", required_argument, NULL, SUN_TIME},
    {"utc-offset", required_argument, NULL, SUN_UTC_OFFSET},
    {"latitude", required_argument, NULL, SUN_LATITUDE},
    {"longitude", required_argument, NULL, SUN_LONGITUDE},
    {"altitude", required_argument, NULL, SUN_ALTITUDE},
    {"refraction", required_argument, NULL, SUN_REFRACTION},
    {"pressure", required_argument, NULL, SUN_PRESSURE},
    {"temperature", required_argument, NULL, SUN_TEMPERATURE},
    {"delta-t", required_argument, NULL, SUN_DELTA_T},
    {"json", no_argument, NULL, SUN_JSON},
    {"help", no_argument, NULL, 'h'},
    {NULL, 0, NULL, 0},
};

/* The library's field names and the flags that set them. */
static const char *const field_flags[][2] = {
    {"date", "--date"},           {"time", "--time"},         {"utc_offset_min", "--utc-offset"},
    {"latitude_deg", "--latitude"}, {"longitude_deg", "--longitude"}, {"elevation_m", "--altitude"},
    {"pressure_mbar", "--pressure"}, {"temperature_c", "--temperature"}, {"delta_t_s", "--delta-t"},
};

/* "[-90, 90]": the library's range of field. */
static const char *range(const char *field, char *buf, size_t size)
{
    const fm_param_range *r = fm_param_range_of(field);
    snprintf(buf, size, "[%g, %g]", r->min, r->max);
    return buf;
}

void sun_print_help(FILE *f)
{
    char lat[32], lon[32], alt[32], p[32], t[32], dt[32];
    fprintf(f, "\n"
            "The sun's apparent position (NREL's Solar Position Algorithm, +-0.0003 deg), the Earth-Sun\n"
            "distance, and sunrise, solar noon and sunset of the date (local clock time of --utc-offset;\n"
            "the sun's centre at -0.8333 deg), or polar day / polar night.\n"
            "\n"
            "  --date YYYY-MM-DD      local date, years 0000-6000 (Julian calendar before 1582-10-15)\n"
            "  --time HH:MM[:SS]      local clock time\n"
            "  --utc-offset +-HH[:MM] local time minus UTC, -12:00 to +14:00 (default +00:00)\n"
            "  --latitude DEG         %s, north positive\n"
            "  --longitude DEG        %s, east positive\n"
            "  --altitude M           observer above sea level, %s (default 0)\n"
            "  --refraction on|off    atmospheric refraction (default on)\n"
            "  --pressure MBAR        for refraction, %s (default 1010)\n"
            "  --temperature C        for refraction, %s (default 10)\n"
            "  --delta-t S            TT - UT in seconds, %s (default: Espenak & Meeus estimate for the\n"
            "                         date)\n"
            "  --json                 one JSON object on stdout\n",
            range("latitude_deg", lat, sizeof lat), range("longitude_deg", lon, sizeof lon),
            range("elevation_m", alt, sizeof alt), range("pressure_mbar", p, sizeof p),
            range("temperature_c", t, sizeof t), range("delta_t_s", dt, sizeof dt));
}

/* Local clock hours to "HH:MM:SS" (rounded to the second). */
static void clock_text(double hours, char *buf, size_t size)
{
    format_time_of_day((int)lround(hours * 3600.0), buf, size);
}

static const char *daylight_name(fm_daylight d)
{
    return d == FM_DAYLIGHT_POLAR_DAY ? "polar day" : (d == FM_DAYLIGHT_POLAR_NIGHT ? "polar night" : "normal");
}

static void print_text(const fm_solar_params *p, const fm_solar_position *o, int delta_t_given)
{
    char t[16], off[8], rise[32], noon[16], set[32];
    format_time_of_day(p->hour * 3600 + p->minute * 60 + (int)p->second, t, sizeof t);
    format_utc_offset(p->utc_offset_min, off, sizeof off);
    clock_text(o->transit_h, noon, sizeof noon);
    if (o->daylight == FM_DAYLIGHT_NORMAL) {
        clock_text(o->sunrise_h, rise, sizeof rise);
        clock_text(o->sunset_h, set, sizeof set);
    } else {
        snprintf(rise, sizeof rise, "none (%s)", daylight_name(o->daylight));
        snprintf(set, sizeof set, "none (%s)", daylight_name(o->daylight));
    }
    printf("time              %04d-%02d-%02d %s UTC%s\n", p->year, p->month, p->day, t, off);
    printf("place             %.6f %c, %.6f %c, %g m\n", fabs(p->latitude_deg), p->latitude_deg < 0 ? 'S' : 'N',
           fabs(p->longitude_deg), p->longitude_deg < 0 ? 'W' : 'E', p->elevation_m);
    if (p->refraction)
        printf("elevation         %.6f deg (apparent, with refraction; %.6f without)\n", o->elevation_deg,
               o->elevation_true_deg);
    else
        printf("elevation         %.6f deg (without refraction)\n", o->elevation_deg);
    printf("azimuth           %.6f deg (from north toward east)\n", o->azimuth_deg);
    printf("zenith            %.6f deg\n", o->zenith_deg);
    printf("earth-sun         %.6f AU\n", o->earth_sun_distance_au);
    printf("sunrise           %s\n", rise);
    printf("solar noon        %s\n", noon);
    printf("sunset            %s\n", set);
    printf("equation of time  %+.2f min\n", o->equation_of_time_min);
    printf("delta T           %.1f s (%s)\n", o->delta_t_s, delta_t_given ? "given" : "Espenak & Meeus estimate");
}

static void print_json(const fm_solar_params *p, const fm_solar_position *o)
{
    char t[16], off[8], rise[16], noon[16], set[16];
    format_time_of_day(p->hour * 3600 + p->minute * 60 + (int)p->second, t, sizeof t);
    format_utc_offset(p->utc_offset_min, off, sizeof off);
    clock_text(o->transit_h, noon, sizeof noon);
    clock_text(o->sunrise_h, rise, sizeof rise);
    clock_text(o->sunset_h, set, sizeof set);
    int normal = o->daylight == FM_DAYLIGHT_NORMAL;
    printf("{\"date\": \"%04d-%02d-%02d\", \"time\": \"%s\", \"utc_offset\": \"%s\", ", p->year, p->month, p->day, t,
           off);
    printf("\"latitude_deg\": %.6f, \"longitude_deg\": %.6f, \"altitude_m\": %g, ", p->latitude_deg, p->longitude_deg,
           p->elevation_m);
    printf("\"refraction\": %s, \"pressure_mbar\": %g, \"temperature_c\": %g, \"delta_t_s\": %.3f, ",
           p->refraction ? "true" : "false", p->pressure_mbar, p->temperature_c, o->delta_t_s);
    printf("\"elevation_deg\": %.6f, \"elevation_without_refraction_deg\": %.6f, \"azimuth_deg\": %.6f, "
           "\"zenith_deg\": %.6f, ",
           o->elevation_deg, o->elevation_true_deg, o->azimuth_deg, o->zenith_deg);
    printf("\"earth_sun_distance_au\": %.8f, \"equation_of_time_min\": %.4f, \"julian_day\": %.6f, ",
           o->earth_sun_distance_au, o->equation_of_time_min, o->julian_day);
    printf("\"day\": \"%s\", ", daylight_name(o->daylight));
    printf(normal ? "\"sunrise\": \"%s\", " : "\"sunrise\": null, ", rise);
    printf("\"solar_noon\": \"%s\", ", noon);
    printf(normal ? "\"sunset\": \"%s\"}\n" : "\"sunset\": null}\n", set);
}

int run_sun(int argc, char **argv)
{
    fm_solar_params p = fm_solar_params_default();
    int json = 0, have_date = 0, have_time = 0, have_lat = 0, have_lon = 0, delta_t_given = 0, seconds = 0, c;
    char msg[512];
    opterr = 0;
    optind = 1;
    int index = -1;
    while ((c = getopt_long(argc, argv, ":h", sun_options, &index)) != -1) {
        const char *arg = optarg;
        char flag[32] = "";
        if (index >= 0)
            snprintf(flag, sizeof flag, "--%s", sun_options[index].name);
        double *target = NULL;
        int ok = 1;
        switch (c) {
        case 'h':
            command_print_help(stdout, command_find("sun", NULL));
            return 0;
        case SUN_DATE:
            ok = parse_date_arg(flag, arg, &p.year, &p.month, &p.day, msg, sizeof msg);
            have_date = 1;
            break;
        case SUN_TIME:
            ok = parse_time_arg(flag, arg, &seconds, msg, sizeof msg);
            p.hour = seconds / 3600;
            p.minute = seconds / 60 % 60;
            p.second = seconds % 60;
            have_time = 1;
            break;
        case SUN_UTC_OFFSET:
            ok = parse_utc_offset_arg(flag, arg, &p.utc_offset_min, msg, sizeof msg);
            break;
        case SUN_REFRACTION:
            ok = parse_on_off_arg(flag, arg, &p.refraction, msg, sizeof msg);
            break;
        case SUN_LATITUDE:
            target = &p.latitude_deg;
            have_lat = 1;
            break;
        case SUN_LONGITUDE:
            target = &p.longitude_deg;
            have_lon = 1;
            break;
        case SUN_ALTITUDE:
            target = &p.elevation_m;
            break;
        case SUN_PRESSURE:
            target = &p.pressure_mbar;
            break;
        case SUN_TEMPERATURE:
            target = &p.temperature_c;
            break;
        case SUN_DELTA_T:
            target = &p.delta_t_s;
            delta_t_given = 1;
            break;
        case SUN_JSON:
            json = 1;
            break;
        case ':':
            report_error("%s needs a value", argv[optind - 1]);
            return 2;
        default:
            report_error("sun: unknown option '%s' (firmament sun --help lists the options)", argv[optind - 1]);
            return 2;
        }
        if (target && !parse_decimal(arg, target)) {
            snprintf(msg, sizeof msg, "%s: '%s' is not a number", flag, arg);
            ok = 0;
        }
        if (!ok) {
            report_error("%s", msg);
            return 2;
        }
        index = -1;
    }
    if (optind < argc) {
        report_error("sun: unexpected argument '%s' (options start with --)", argv[optind]);
        return 2;
    }
    if (!have_date || !have_time || !have_lat || !have_lon) {
        report_error("sun: needs %s", !have_date ? "--date" : (!have_time ? "--time" : (!have_lat ? "--latitude"
                                                                                                    : "--longitude")));
        return 2;
    }
    fm_solar_position o;
    fm_error err = {0};
    if (fm_solar_position_compute(&p, &o, &err) != FM_OK) {
        size_t n = strlen(err.parameter);
        for (size_t i = 0; i < sizeof field_flags / sizeof field_flags[0]; i++)
            if (n && strcmp(err.parameter, field_flags[i][0]) == 0 && strncmp(err.message, err.parameter, n) == 0) {
                report_error("%s%s", field_flags[i][1], err.message + n);
                return 2;
            }
        report_error("%s", err.message);
        return 2;
    }
    if (json)
        print_json(&p, &o);
    else
        print_text(&p, &o, delta_t_given);
    return 0;
}
