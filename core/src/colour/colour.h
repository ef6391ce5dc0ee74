/* Colour: CIE XYZ to linear Rec.709 (sRGB primaries, D65 white) with the plain matrix that
 * Blender's OpenColorIO configuration uses (srgb_to_xyz.spimtx), no chromatic adaptation, so "XYZ"
 * means the same in Blender and in firmament.  Sunlight is not white-balanced. */
#ifndef FM_COLOUR_COLOUR_H
#define FM_COLOUR_COLOUR_H

/* Rec.709 -> XYZ, rows X, Y, Z (IEC 61966-2-1 / Blender). */
extern const double fm_rec709_to_xyz[3][3];

void colour_xyz_to_rec709(const double xyz[3], double rgb[3]);
void colour_rec709_to_xyz(const double rgb[3], double xyz[3]);

/* inv = m^-1 and out = m in, for a row-major 3x3 matrix m given as &m[0][0]. */
void colour_matrix_inverse(const double *m, double inv[3][3]);
void colour_matrix_apply(const double *m, const double in[3], double out[3]);

/* The RGB -> XYZ matrix of an EXR's chromaticities (R, G, B, W as x, y pairs; RGB = 1 gives the
 * white with Y = 1); the XYZ convention R (1,0), G (0,1), B (0,0) gives the identity.  Returns 0
 * when they describe no colour space (a primary or the white with y <= 0, collinear primaries). */
int colour_matrix_from_chromaticities(const float c[8], double m[3][3]);

/* CIE xy chromaticities of the Rec.709 primaries and D65 white: R, G, B, W as (x, y) pairs. */
extern const float fm_rec709_chromaticities[8];

#endif
