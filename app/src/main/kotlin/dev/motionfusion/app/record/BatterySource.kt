package dev.motionfusion.app.record

import android.content.Context
import android.content.Intent
import android.content.IntentFilter
import android.os.BatteryManager
import androidx.core.content.ContextCompat

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
