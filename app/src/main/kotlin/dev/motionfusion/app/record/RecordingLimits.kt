package dev.motionfusion.app.record

import android.content.Context
import android.content.Intent
import android.content.IntentFilter
import android.os.BatteryManager
import androidx.core.content.ContextCompat

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

        /** 5 %: stops early enough for the phone to close the session and still be usable. */
        const val DEFAULT_STOP_BATTERY_PERCENT = 5
        const val MAX_DURATION_LIMIT_S = 7 * 24 * 3600L
        const val MAX_STOP_BATTERY_PERCENT = 50
    }
}

/** The battery as the recording needs it: charge in % (null when unknown) and whether it is charging. */
data class BatteryState(val percent: Int?, val charging: Boolean)

/** Where the recording service reads the battery: ACTION_BATTERY_CHANGED in the app ([StickyBattery]), a fake in tests. */
fun interface BatterySource {
    fun read(): BatteryState
}

/** The battery of the device, from the sticky ACTION_BATTERY_CHANGED broadcast (no receiver kept). */
internal class StickyBattery(private val context: Context) : BatterySource {
    override fun read(): BatteryState {
        val i = ContextCompat.registerReceiver(context, null, IntentFilter(Intent.ACTION_BATTERY_CHANGED), ContextCompat.RECEIVER_NOT_EXPORTED)
            ?: return BatteryState(null, false)
        val level = i.getIntExtra(BatteryManager.EXTRA_LEVEL, -1)
        val scale = i.getIntExtra(BatteryManager.EXTRA_SCALE, -1)
        return BatteryState(if (level >= 0 && scale > 0) level * 100 / scale else null, i.getIntExtra(BatteryManager.EXTRA_PLUGGED, 0) != 0)
    }
}
