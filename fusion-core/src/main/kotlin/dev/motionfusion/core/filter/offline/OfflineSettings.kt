/*
 * Settings of the offline estimate (`fusion replay --offline`, OfflinePasses.kt) beyond the filter's own.
 * Angles rad, noise densities rad·√s, rad/√s, rad/s/√s.
 */
package dev.motionfusion.core.filter.offline

import kotlin.math.PI

/**
 * Settings of the offline estimate beyond the filter's own ([dev.motionfusion.core.filter.FilterSettings]
 * applies to every pass alike). All chosen by cross-validation (docs/ACCURACY.md, "Offline").
 *
 * @property backwardWeight the backward pass's weight in the combination's heading (the rotation between the
 *   two passes' estimates about the vertical), 0…1, where neither pass has met a disturbed field lately; where
 *   one has, the other gets more ([Blend.headingWeight]).
 * @property inclinationBackwardWeight the backward pass's weight in the combination's inclination (the
 *   rotation about a horizontal axis), 0…1.
 * @property headingSmoothing how far the combination's heading is then turned towards the heading smoother's
 *   ([HeadingSmoother]), 0…1; 0 leaves the smoother out.
 * @property smootherRestNoise the smoother's magnetometer heading noise while the rest detector says the device
 *   is at rest, as a density, rad·√s (the variance of one reading is its square over the step length).
 * @property smootherMotionNoise the same in motion, rad·√s.
 * @property smootherHeadingNoise the random walk of the heading the gyroscope integrates, rad/√s.
 * @property smootherBiasNoise the random walk of the gyroscope's bias about the vertical, rad/s/√s.
 * @property smootherRestSpread the largest spread of the field's magnitude while the device moves (a robust
 *   standard deviation, 1.4826 × the median absolute deviation, relative to the median magnitude) at which the
 *   smoother gives rest its trust ([smootherRestNoise]); above it a rest's readings count as the motion's
 *   ([smootherMotionNoise]); [Double.POSITIVE_INFINITY] trusts every rest. A magnitude that changes as the
 *   device turns means a magnetometer that is not calibrated or carries a magnet along: its heading error then
 *   depends on the orientation, and a rest holds one orientation's error however long it lasts
 *   (docs/ACCURACY.md, "Trust at rest only in a steady field").
 * @property buildingPersistence the field persistence, degrees (the first pass's judgement of the whole recording,
 *   Replayer.fieldPersistenceDeg), above which every pass runs without the bias estimate in motion
 *   (FilterSettings.motionBiasGain off; the first pass again over the temporary file): a field whose heading strays
 *   from the gyroscope's for minutes teaches the gyroscope a wrong bias. The heading still follows the field, and the
 *   heading smoother still learns the bias about the vertical. Not with the magnetic trust on
 *   (FilterSettings.magTrustSpread), which weighs that estimate by the field's wander already.
 *   [Double.POSITIVE_INFINITY]: never. Default [BUILDING_PERSISTENCE_DEG] (docs/ACCURACY.md, "Does the recording
 *   look like a building?").
 */
public data class OfflineSettings @JvmOverloads constructor(
    val backwardWeight: Double = 0.0,
    val inclinationBackwardWeight: Double = 0.5,
    val headingSmoothing: Double = 0.8,
    val smootherRestNoise: Double = 1.0 * DEGREE,
    val smootherMotionNoise: Double = 30.0 * DEGREE,
    val smootherHeadingNoise: Double = 0.02 * DEGREE,
    val smootherBiasNoise: Double = 0.005 * DEGREE,
    val smootherRestSpread: Double = 0.04,
    val buildingPersistence: Double = BUILDING_PERSISTENCE_DEG,
) {
    init {
        require(backwardWeight in 0.0..1.0) { "backwardWeight must be within 0…1, not $backwardWeight" }
        require(inclinationBackwardWeight in 0.0..1.0) { "inclinationBackwardWeight must be within 0…1, not $inclinationBackwardWeight" }
        require(headingSmoothing in 0.0..1.0) { "headingSmoothing must be within 0…1, not $headingSmoothing" }
        for ((name, v) in listOf(
            "smootherRestNoise" to smootherRestNoise, "smootherMotionNoise" to smootherMotionNoise,
            "smootherHeadingNoise" to smootherHeadingNoise, "smootherBiasNoise" to smootherBiasNoise,
        )) require(v.isFinite() && v > 0.0) { "$name must be finite and > 0, not $v" }
        require(smootherRestSpread > 0.0) { "smootherRestSpread must be > 0 (infinite: rest always trusted), not $smootherRestSpread" }
        require(buildingPersistence > 0.0) { "buildingPersistence must be > 0 (infinite: never), not $buildingPersistence" }
    }

    public companion object {
        private const val DEGREE = PI / 180.0

        /**
         * The field persistence (degrees, Replayer.fieldPersistenceDeg) above which a recording's field looks like a
         * building's: above every recording of BROAD's rig and of Tyrex's and OxIOD's rooms (at most 6.2°), below
         * seven of ADVIO's ten walks indoors (docs/ACCURACY.md).
         */
        public const val BUILDING_PERSISTENCE_DEG: Double = 7.5

        /** The size of the offline replay's temporary file, bytes per output row. */
        public const val SPILL_BYTES_PER_ROW: Int = Spill.RECORD
    }
}
