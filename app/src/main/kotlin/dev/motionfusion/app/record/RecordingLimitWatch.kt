package dev.motionfusion.app.record

import dev.motionfusion.app.settings.RecordingLimits

/**
 * The limits of the settings ([RecordingLimits]) for one recording started at [startedElapsedMs] (elapsed realtime):
 * its maximum duration, and the battery level, read from [battery] every [BATTERY_CHECK_NS] (it changes slowly) while
 * not charging. Asked once a second on the injected clock.
 */
internal class RecordingLimitWatch(
    private val limits: RecordingLimits,
    private val startedElapsedMs: Long,
    private val battery: BatterySource,
) {
    private var batteryCheckedNs = Long.MIN_VALUE / 2

    /** The limit reached at [nowNs] (elapsed realtime), or null. */
    fun reached(nowNs: Long): RecordingEnd? {
        val max = limits.maxDurationS
        if (max > 0 && nowNs - startedElapsedMs * 1_000_000 >= max * 1_000_000_000) return RecordingEnd.MaxDuration(max)
        if (limits.stopBatteryPercent > 0 && nowNs - batteryCheckedNs >= BATTERY_CHECK_NS) {
            batteryCheckedNs = nowNs
            val b = battery.read()
            val percent = b.percent
            if (!b.charging && percent != null && percent <= limits.stopBatteryPercent) return RecordingEnd.BatteryLow(percent)
        }
        return null
    }

    companion object {
        /** The battery level is read every 30 s. */
        const val BATTERY_CHECK_NS = 30_000_000_000L
    }
}
