//! Planners for tethered robots: A* over the shortest path tree (thesis Alg. 3-4), ascent
//! feasibility and path pairs (Alg. 5-6), frictional and online planning (Ch. 3), and an
//! ABIT*-style sampler with anchor histories (Paton §V). Depends on terrain and robot traits only.
