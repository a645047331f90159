package dev.motionfusion.app.record

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
    }

    @Volatile var state: State = State.Idle
        internal set

    val isRecording: Boolean get() = state is State.Active
}

/** Seams for tests: the session format and the queue size the service uses. */
internal object RecordingDeps {
    @Volatile var format: SessionFormat = CoreSessionFormat

    /** Slots in the queue between sensors and writer (36 bytes each): 2^17 ≈ 4.7 MB, ~37 s of 7 streams at 500 Hz. */
    @Volatile var ringCapacity: Int = 1 shl 17

    /** Recording stops cleanly when free space falls below this. */
    @Volatile var minFreeBytes: Long = 32L * 1024 * 1024

    fun reset() {
        format = CoreSessionFormat
        ringCapacity = 1 shl 17
        minFreeBytes = 32L * 1024 * 1024
    }
}
