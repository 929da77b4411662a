/* Minimal useful build: a DPD solvent and nothing else. */
#define DPD
