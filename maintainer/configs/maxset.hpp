/* Everything that can be on at once (DPD_MASS_LIN excludes DPD_MASS_RED). */
#define ROTATION
#define MASS
#define EXTERNAL_FORCE
#define LENNARD_JONES
#define HAT
#define DPD
#define TRANS_DPD
#define DPD_MASS_RED
#define MARBLE
#define TUNABLE_SLIP
#define SRD
