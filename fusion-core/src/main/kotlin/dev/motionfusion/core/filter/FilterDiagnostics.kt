/*
 * Read-only diagnostics of MadgwickFilter: what the filter believes about its inputs.
 * Bias in rad/s in the Android device frame.
 */
package dev.motionfusion.core.filter

import dev.motionfusion.core.Vector3

/**
 * A copy of the filter's internal flags and counters at one instant.
 *
 * @property initialised the filter has an orientation (see [Initialisation]).
 * @property gyroBias the gyroscope bias subtracted from each reading (rest estimate and ζ), rad/s,
 *   device frame.
 * @property atRest the rest detector currently sees the sensor at rest.
 * @property magneticDisturbance the magnetometer is currently left out as disturbed (by the disturbance
 *   detector, or a field stronger than any earth field: SensorRanges.MAX_EARTH_FIELD_UT, 200 µT), or the
 *   magnetic trust (magTrustSpread) holds the heading on the gyroscope (heading gain below a quarter).
 * @property accelerometerRejected the accelerometer is currently left out (linear acceleration).
 * @property gyroscopeSteps gyroscope samples integrated.
 * @property skippedBeforeInit gyroscope samples dropped while waiting for initialisation.
 * @property skippedNonFinite samples (any sensor) with a NaN or infinite value, dropped, and steps
 *   whose result was not finite (absurd readings), not applied.
 * @property skippedOutOfRange samples (any sensor) with an axis beyond any phone's range
 *   (SensorRanges: 100 rad/s, 50 g, 5000 µT), dropped.
 * @property skippedZero accelerometer or magnetometer samples of zero length, dropped.
 * @property skippedTimestamp gyroscope samples whose timestamp did not advance, dropped.
 * @property skippedGap gyroscope samples after a gap longer than maxGap, not integrated.
 * @property staleSamples gyroscope steps whose latest accelerometer or magnetometer sample was older
 *   than maxGap and therefore not used.
 * @property accelerometerRejections steps whose accelerometer reading was rejected.
 * @property magneticRejections steps whose magnetometer reading was rejected as disturbed (by the detector,
 *   or stronger than any earth field).
 * @property gyroscopeSaturations gyroscope readings with an axis at or beyond gyroSaturation (clipped
 *   at the sensor's range), after which inclination and heading re-converge fast.
 * @property magnetometerOffset the hard-iron offset taken off the latest magnetometer reading (hardIronThreshold;
 *   HardIronEstimate.kt), µT, device frame; zero while none is (a reading beyond the earth's field stays as read), or
 *   without the estimate.
 */
public data class FilterDiagnostics(
    val initialised: Boolean,
    val gyroBias: Vector3,
    val atRest: Boolean,
    val magneticDisturbance: Boolean,
    val accelerometerRejected: Boolean,
    val gyroscopeSteps: Long,
    val skippedBeforeInit: Long,
    val skippedNonFinite: Long,
    val skippedZero: Long,
    val skippedTimestamp: Long,
    val skippedGap: Long,
    val staleSamples: Long,
    val accelerometerRejections: Long,
    val magneticRejections: Long,
    val gyroscopeSaturations: Long = 0,
    val skippedOutOfRange: Long = 0,
    val magnetometerOffset: Vector3 = Vector3.ZERO,
)
