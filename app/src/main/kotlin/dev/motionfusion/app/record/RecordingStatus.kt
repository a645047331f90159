package dev.motionfusion.app.record

import android.app.Notification
import android.app.Service
import androidx.core.app.ServiceCompat
import java.io.File

/**
 * The recording state of the process, for screens to show: written by [RecordingService] on
 * the main thread, read by anyone. Screens poll it while visible.
 */
internal object RecordingStatus {
    sealed interface State {
        data object Idle : State

        data class Active(
            val session: File,
            /** `SystemClock.elapsedRealtime()` when recording started. */
            val startedElapsedMs: Long,
            val rows: () -> Long,
        ) : State

        data class Ended(val session: File, val result: RecorderResult) : State

        /** The system refused to start the recording (no foreground service allowed now, a permission missing). */
        data class NotStarted(val reason: String) : State
    }

    @Volatile var state: State = State.Idle
        internal set

    val isRecording: Boolean get() = state is State.Active
}

/** Seams for tests: the session format, the queue size and the way into the foreground the service uses. */
internal object RecordingDeps {
    @Volatile var format: SessionFormat = CoreSessionFormat

    /** Enters the foreground (ServiceCompat.startForeground); tests make it refuse as the system can. */
    @Volatile var startForeground: (Service, Int, Notification, Int) -> Unit = ::enterForeground

    /** Slots in the queue between sensors and writer (36 bytes each): 2^17 ≈ 4.7 MB, ~37 s of 7 streams at 500 Hz. */
    @Volatile var ringCapacity: Int = 1 shl 17

    /** Recording stops cleanly when free space falls below this. */
    @Volatile var minFreeBytes: Long = 32L * 1024 * 1024

    fun reset() {
        format = CoreSessionFormat
        ringCapacity = 1 shl 17
        minFreeBytes = 32L * 1024 * 1024
        startForeground = ::enterForeground
    }

    private fun enterForeground(service: Service, id: Int, notification: Notification, type: Int) =
        ServiceCompat.startForeground(service, id, notification, type)
}
