/* Everything that can be on at once: every feature of features.def (new ones
 * included automatically) except DPD_MASS_LIN, which excludes DPD_MASS_RED. */
#define MARBLE_ALL_FEATURES
#undef DPD_MASS_LIN
