package dev.motionfusion.app.sensor

/**
 * The filter's gyroscope saturation threshold (FilterSettings.gyroSaturation) from the device's
 * gyroscope range (Sensor.getMaximumRange(), rad/s): [MARGIN] of it, so that readings clipped at
 * the range, or one resolution step below it, count as saturated, while the fastest unclipped
 * motion (a few percent below the range) does not. A range that is missing or implausible
 * (below 1 rad/s, about 57°/s, which no phone gyroscope has) keeps the filter's default. A range
 * above [DEGREES_ABOVE] is a driver reporting °/s, as some do (125 … 4000): taken as °/s and
 * converted, since read as rad/s it would put the threshold beyond any reading and turn the
 * detection off without a word.
 */
internal object GyroSaturation {
    /** 97 %: about 1 rad/s below the common ±2000°/s (34.9 rad/s) range, the margin of the filter's default (34 rad/s). */
    const val MARGIN = 0.97

    /** Phone gyroscopes reach at most ±4000°/s (69.8 rad/s); a larger "rad/s" range is in °/s. */
    const val DEGREES_ABOVE = 100.0

    /** The range in rad/s of a gyroscope whose driver reports [maximumRange], or null when it is missing or implausible. */
    fun rangeRadS(maximumRange: Float?): Double? {
        val r = maximumRange?.toDouble() ?: return null
        if (!r.isFinite() || r < 1.0) return null
        return if (r > DEGREES_ABOVE) Math.toRadians(r) else r
    }

    /** The threshold for a gyroscope whose driver reports [maximumRange], or null to keep the default. */
    fun fromRange(maximumRange: Float?): Double? = rangeRadS(maximumRange)?.let { it * MARGIN }
}
