/* DPD with friction scaled by the arithmetic mean mass (implies MASS). */
#define DPD_MASS_LIN
