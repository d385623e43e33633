//! VectorNav VN-200 GNSS/INS (ICD for firmware 2.1.0.0): binary output messages, the ASCII command
//! protocol and registers. (Implemented by the VN-200 driver issue.)
