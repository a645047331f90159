/*
 * The plausibility limits of the inputs, in one place (docs/IMPORT.md, "Plausibility", lists them
 * with their messages). A reading beyond a limit is no phone's measurement: the filter skips and
 * counts it (FilterDiagnostics.skippedOutOfRange); the import's probe (input/Plausibility.kt)
 * uses the rates and typical magnitudes to tell a wrong unit.
 */
package dev.motionfusion.core.filter

import dev.motionfusion.core.STANDARD_GRAVITY

internal object SensorRanges {
    /** Largest |ω| per axis, rad/s: phones' gyroscopes end at ±2000 °/s (34.9 rad/s); about three times that. */
    const val GYROSCOPE_RAD_S = 100.0

    /** Largest |a| per axis, m/s²: phones' accelerometers end at ±16 g (157 m/s²); 50 g. */
    const val ACCELEROMETER_M_S2 = 50 * STANDARD_GRAVITY

    /** Largest |B| per axis, µT: phones' magnetometers end at ±4900 µT (AK09918 class); 5000 µT. */
    const val MAGNETOMETER_UT = 5000.0

    /**
     * Largest field, µT, that can still carry a heading. The earth's is at most about 67 µT (at the magnetic
     * poles); near steel or a magnet a calibrated phone reads more for a moment (the Tyrex subset's disturbed
     * recordings: 162 µT at most), and the filter's own mechanisms handle that. Beyond this the reading is a
     * magnet held to the phone or a magnetometer whose hard-iron offset was never removed (a raw reading:
     * hundreds of µT), so its direction is no heading: the filter and the offline heading smoother leave it out
     * ([isEarthField]), and a recording whose field is always stronger runs without heading.
     */
    const val MAX_EARTH_FIELD_UT = 200.0

    /** Whether a field of (x, y, z) µT can be the earth's: finite, not zero, at most [MAX_EARTH_FIELD_UT]. */
    fun isEarthField(x: Double, y: Double, z: Double): Boolean {
        val n2 = x * x + y * y + z * z
        return n2 > 0.0 && n2 <= MAX_EARTH_FIELD_UT * MAX_EARTH_FIELD_UT
    }

    /** Lowest sampling rate a replay accepts, Hz (real exports decimated to 5 Hz still replay). */
    const val MIN_RATE_HZ = 3.0

    /** Highest sampling rate a replay accepts, Hz (phones sample at most a few kHz). */
    const val MAX_RATE_HZ = 10_000.0

    /** Median |a| over a stream below this is no accelerometer in m/s² (gravity alone is 9.8). */
    const val MIN_MEDIAN_ACCELEROMETER_M_S2 = 3.0

    /** Median |a| above this: no phone held by a person (3 g throughout). */
    const val MAX_MEDIAN_ACCELEROMETER_M_S2 = 30.0

    /** Median |ω| above this, rad/s, is a gyroscope in °/s (a sustained 290 °/s; in °/s a slowly turned phone reads more). */
    const val MAX_MEDIAN_GYROSCOPE_RAD_S = 5.0

    /** Median |B| below this, µT, is no magnetometer in µT (the earth's field is 25–65 µT): gauss or zero. */
    const val MIN_MEDIAN_MAGNETOMETER_UT = 5.0

    /**
     * Median |B| above this, µT: nT or a magnet held to the phone throughout. A raw magnetometer
     * with a large hard iron (what `fusion calibrate` corrects) reads up to the sensor's range, ±4900 µT.
     */
    const val MAX_MEDIAN_MAGNETOMETER_UT = 5000.0

    /** A gyroscope timestamp stepping back by more than this, s, is a recording out of order. */
    const val MAX_STEP_BACK_S = 1.0
}
