/* No optional features: plain velocity-Verlet point particles. */
