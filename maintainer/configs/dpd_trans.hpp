/* DPD with the transverse (TRANS_DPD) friction. */
#define DPD
#define TRANS_DPD
