package dev.motionfusion.app.sensor

/**
 * The filter's gyroscope saturation threshold (FilterSettings.gyroSaturation) from the device's
 * gyroscope range (Sensor.getMaximumRange(), rad/s): [MARGIN] of it, so that readings clipped at
 * the range, or one resolution step below it, count as saturated, while the fastest unclipped
 * motion (a few percent below the range) does not. A range that is missing or implausible
 * (below 1 rad/s, about 57°/s, which no phone gyroscope has) keeps the filter's default.
 */
internal object GyroSaturation {
    /** 97 %: about 1 rad/s below the common ±2000°/s (34.9 rad/s) range, the margin of the filter's default (34 rad/s). */
    const val MARGIN = 0.97

    /** The threshold for a gyroscope of range [maximumRangeRadS], or null to keep the default. */
    fun fromRange(maximumRangeRadS: Float?): Double? {
        val r = maximumRangeRadS?.toDouble() ?: return null
        if (!r.isFinite() || r < 1.0) return null
        return r * MARGIN
    }
}
