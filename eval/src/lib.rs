//! How trackd's tracks are judged (`../shared/eval-protocol.md`): ground truth from simulated
//! drives and KITTI labels, BEV centre matching, CLEAR MOT, IDF1 and HOTA.

#![warn(missing_docs)]
