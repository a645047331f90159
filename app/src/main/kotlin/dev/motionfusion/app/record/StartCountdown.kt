package dev.motionfusion.app.record

import android.os.Handler
import android.os.Looper
import kotlinx.coroutines.flow.MutableStateFlow
import kotlinx.coroutines.flow.StateFlow
import kotlinx.coroutines.flow.asStateFlow

/**
 * Record after a delay (the setting "Start recording after"): the seconds left, counted down once a second on the main
 * thread, then [start]'s action runs, which starts the recording, so the session's first sample comes after the
 * countdown. Held by [Recordings], so that a rotation keeps it; [cancel] drops it (the record bar's Cancel, or the
 * screen left: Android 12+ refuses the recording's foreground service to an app started from the background).
 */
class StartCountdown {
    private val handler = Handler(Looper.getMainLooper())
    private val left = MutableStateFlow(0)
    private var action: (() -> Unit)? = null

    /** Seconds until the recording starts; 0: no countdown. */
    val secondsLeft: StateFlow<Int> = left.asStateFlow()

    val isRunning: Boolean get() = left.value > 0

    private val tick = object : Runnable {
        override fun run() {
            val n = left.value - 1
            left.value = n
            if (n > 0) {
                handler.postDelayed(this, 1_000)
            } else {
                val a = action
                action = null
                a?.invoke()
            }
        }
    }

    /** Counts [seconds] down, then runs [action]; [seconds] ≤ 0 runs it at once. Main thread. */
    fun start(seconds: Int, action: () -> Unit) {
        cancel()
        if (seconds <= 0) return action()
        this.action = action
        left.value = seconds
        handler.postDelayed(tick, 1_000)
    }

    /** No recording starts; nothing was recorded. Main thread. */
    fun cancel() {
        handler.removeCallbacks(tick)
        action = null
        left.value = 0
    }
}
