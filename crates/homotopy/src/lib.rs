//! Homotopy of tether paths in a boundary-triangulated 2-manifold (thesis §2.2-2.3): crossing
//! sequences and their reduction, sleeves, the funnel algorithm, shortest homotopic paths (SHPs),
//! H-signatures, and funnel states on the universal cover. Knows nothing of friction or robots.
