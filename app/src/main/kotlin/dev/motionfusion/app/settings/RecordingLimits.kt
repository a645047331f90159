package dev.motionfusion.app.settings

/**
 * When a recording stops by itself, validated: after [maxDurationS] seconds (0: no limit), or
 * when the battery, not charging, is at or below [stopBatteryPercent] (0: never). The session's
 * meta.json says which (`end_reason` "max_duration" or "battery_low").
 */
data class RecordingLimits(
    val maxDurationS: Long = 0L,
    val stopBatteryPercent: Int = DEFAULT_STOP_BATTERY_PERCENT,
) {
    init {
        require(maxDurationS in 0L..MAX_DURATION_LIMIT_S) { "maximum duration must be 0..$MAX_DURATION_LIMIT_S s, got $maxDurationS" }
        require(stopBatteryPercent in 0..MAX_STOP_BATTERY_PERCENT) { "battery stop level must be 0..$MAX_STOP_BATTERY_PERCENT %, got $stopBatteryPercent" }
    }

    companion object {
        /** The choices the settings offer for the maximum duration, s (0: no limit). */
        val DURATION_CHOICES_S: List<Long> = listOf(0L, 5 * 60L, 15 * 60L, 30 * 60L, 3600L, 2 * 3600L, 6 * 3600L, 12 * 3600L)

        /** The choices the settings offer for the battery stop level, % (0: never). */
        val BATTERY_CHOICES: List<Int> = listOf(0, 5, 10, 15, 20, 30)

        /**
         * The Noise (still) recording's own limits, whatever the user set for ordinary recordings:
         * it asks for 1–3 h, so it stops at 3 h (a forgotten one does not run all night) and at the
         * default battery level.
         */
        val STILL = RecordingLimits(maxDurationS = 3 * 3600L, stopBatteryPercent = DEFAULT_STOP_BATTERY_PERCENT)

        /** 5 %: stops early enough for the phone to close the session and still be usable. */
        const val DEFAULT_STOP_BATTERY_PERCENT = 5
        const val MAX_DURATION_LIMIT_S = 7 * 24 * 3600L
        const val MAX_STOP_BATTERY_PERCENT = 50
    }
}
