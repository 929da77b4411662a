/* Default configuration: every feature that keeps standard physics.
 * The mass-weighted DPD variants (DPD_MASS_RED / DPD_MASS_LIN) change the
 * friction of unequal-mass pairs and are mutually exclusive: opt in. */
#define ROTATION
#define MASS
#define EXTERNAL_FORCE
#define LENNARD_JONES
#define HAT
#define MORSE
#define CONTACT
#define DPD
#define TRANS_DPD
#define MARBLE
#define TUNABLE_SLIP
#define SRD
#define LUBRICATION
