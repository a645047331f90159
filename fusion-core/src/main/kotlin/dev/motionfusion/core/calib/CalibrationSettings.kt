/*
 * Settings of the calibration fits (validated, immutable). Units SI: s, rad/s, m/s², µT.
 */
package dev.motionfusion.core.calib

import dev.motionfusion.core.STANDARD_GRAVITY

/**
 * @property magModel the magnetometer's ellipsoid model (FULL: hard and soft iron; SPHERE: hard iron only).
 * @property minCoverage the fraction of the sphere of directions the magnetometer must cover, else the fit is refused.
 * @property maxResidualFraction largest accepted RMS residual of the magnetometer fit, as a fraction of the field strength.
 * @property maxMagSamples magnetometer samples kept for the fit; longer recordings are thinned evenly.
 * @property stillWindowS length of the windows in which stillness is judged, s.
 * @property gyroStillStd a window is still when the gyroscope's standard deviation on every axis is below this, rad/s …
 * @property accStillStd … and the accelerometer's below this, m/s².
 * @property minStillS least total still time for a gyroscope bias, s.
 * @property minPoseS least still time of one accelerometer pose, s.
 * @property poseSeparation angle between the gravity directions of two poses for them to count as distinct, rad.
 * @property gravity the magnitude of gravity the accelerometer is scaled to, m/s² (the earth's, 9.7–9.9).
 */
public data class CalibrationSettings(
    val magModel: EllipsoidModel = EllipsoidModel.FULL,
    val minCoverage: Double = 0.3,
    val maxResidualFraction: Double = 0.1,
    val maxMagSamples: Int = 100_000,
    val stillWindowS: Double = 1.0,
    val gyroStillStd: Double = 0.01,
    val accStillStd: Double = 0.1,
    val minStillS: Double = 5.0,
    val minPoseS: Double = 2.0,
    val poseSeparation: Double = Math.toRadians(20.0),
    val gravity: Double = STANDARD_GRAVITY,
) {
    init {
        require(magModel != EllipsoidModel.AXIS_ALIGNED) { "magModel must be FULL or SPHERE" }
        require(minCoverage in 0.0..1.0) { "minCoverage must be in [0, 1]: $minCoverage" }
        require(maxResidualFraction > 0.0 && maxResidualFraction.isFinite()) { "maxResidualFraction must be > 0" }
        require(maxMagSamples >= 100) { "maxMagSamples must be ≥ 100" }
        for ((name, v) in listOf(
            "stillWindowS" to stillWindowS, "gyroStillStd" to gyroStillStd, "accStillStd" to accStillStd,
            "minStillS" to minStillS, "minPoseS" to minPoseS, "poseSeparation" to poseSeparation, "gravity" to gravity,
        )) require(v.isFinite() && v > 0.0) { "$name must be finite and > 0: $v" }
        require(minPoseS >= stillWindowS) { "minPoseS must be at least stillWindowS" }
        // The earth's gravity is 9.76–9.84 m/s² from the equator to the poles and up mountains: anything else scales every reading wrongly.
        require(gravity in 9.7..9.9) { "gravity must be the earth's, 9.7–9.9 m/s² (local gravity, or 9.80665): $gravity" }
    }
}
