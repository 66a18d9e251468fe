//! hamel's validation suite lives in `tests/`: each file checks the generated simulators
//! against something nobody here wrote (closed forms from the literature, an independent
//! projected-Lagrange formulation, num-dual, rustc's own compilation of the same bodies).
