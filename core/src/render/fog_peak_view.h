/* How the light of the droplets' truncated peak (fog_peak.h) seen along a view compares with the
 * table's, which holds it as it comes along the sun's slant: a view below a low sun sees it cross
 * more fog, one above less.  A table by view elevation per grid wavelength, for fog around the
 * observer. */
#ifndef FM_RENDER_FOG_PEAK_VIEW_H
#define FM_RENDER_FOG_PEAK_VIEW_H

/* The weights' nodes: uniform in view elevation from the horizon, one on the sun's, to the top of
 * the peak's table above the sun (1.1 degrees apart at sun 8), read in logarithms. */
#define FOG_PEAK_VIEWS 48
/* Per wavelength: the nodes' spacing in elevation (rad; 0: no weights, every one 1), the shell's
 * 2 H / R, then the nodes' logarithms. */
#define FOG_PEAK_VIEW_SIZE (FOG_PEAK_VIEWS + 2)

/* The weights w (FOG_PEAK_VIEW_SIZE) for fog of optical depth tau above the observer (H m of it
 * under a sphere of R m: shell = 2 H / R) whose peak scatters albedo of its extinction, the sun at
 * cosine mu0, nodes from the horizon to top_rad. */
void fog_peak_view_fill(double *w, double tau, double albedo, double shell, double mu0, double top_rad);
/* The weight at view cosine mu (that of the horizon below it): 1 at the sun's elevation. */
double fog_peak_view(const double *w, double mu);

/* Where view cosine mu falls among the nodes of weights whose spacing and shell (w[0], w[1]) are
 * these: the same for every wavelength of a column (its geometry), so a view is placed once. */
typedef struct fog_peak_view_place {
    double spacing, shell; /* the weights' w[0], w[1] it was placed among */
    int i;                 /* the node below */
    double t;              /* the fraction toward the next, linear in the secant's inverse */
} fog_peak_view_place;
fog_peak_view_place fog_peak_view_placed(const double *w, double mu);
/* fog_peak_view(w, mu) for weights w with p's spacing and shell (or none: 1). */
double fog_peak_view_read(const double *w, const fog_peak_view_place *p);

#endif
