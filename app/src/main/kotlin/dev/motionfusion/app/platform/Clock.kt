package dev.motionfusion.app.platform

import android.os.SystemClock

/** The clocks the app reads, injected so that tests set the time. */
interface Clock {
    /** `SystemClock.elapsedRealtimeNanos()`: the time base of sensor timestamps. */
    fun elapsedRealtimeNanos(): Long

    /** `System.currentTimeMillis()`. */
    fun wallClockMs(): Long

    /** The device's clocks. */
    object System : Clock {
        override fun elapsedRealtimeNanos(): Long = SystemClock.elapsedRealtimeNanos()
        override fun wallClockMs(): Long = java.lang.System.currentTimeMillis()
    }
}
