// Scheduling weight of the pipeline's background threads. Tracking has a deadline (the
// next frame); local mapping and loop closure only have to keep up. On a two-core robot
// computer the three compete, and a keyframe's bundle adjustment would otherwise slow the
// frames tracked meanwhile. A higher nice value makes the scheduler prefer the tracking
// threads while leaving the background threads every idle cycle between frames.
//
// Thread safety: affects the calling thread only.
#pragma once

namespace plslam {

/// Sets the calling thread's nice value to `nice` (0..19; 0 leaves it as it is). Returns
/// false when the system refused (the thread runs on at its old priority).
bool setThisThreadNice(int nice);

}  // namespace plslam
