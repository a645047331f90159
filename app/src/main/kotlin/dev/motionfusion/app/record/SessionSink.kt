package dev.motionfusion.app.record

import dev.motionfusion.app.settings.RecordingLimits
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.sync.ClockExchange
import java.io.IOException

/**
 * Where the writer thread puts a recording: the session format's streaming writer behind a
 * small interface, so the queue, the writer loop and their failure handling are tested with
 * fakes. Called from the writer thread only. Any method may throw [IOException] (disk full,
 * storage removed): the recording then stops, and what reached the storage stays there.
 */
internal interface SessionSink {
    /** One raw sensor row: [SessionStream.valueCount] values at [values]`[offset..]`. */
    @Throws(IOException::class)
    fun raw(stream: SessionStream, timestampNs: Long, accuracy: Int, values: FloatArray, offset: Int)

    /**
     * One row of the live fused orientation, written after the gyroscope row at [timestampNs]
     * that stepped the filter: quaternion [w, x, y, z], Hamilton, sensor→ENU, at
     * [q]`[offset..offset+3]`.
     */
    @Throws(IOException::class)
    fun fused(timestampNs: Long, q: DoubleArray, offset: Int)

    /** The live filter's gyroscope bias estimate (rad/s, device frame) and flags at [timestampNs]. */
    @Throws(IOException::class)
    fun diagnostics(timestampNs: Long, biasX: Double, biasY: Double, biasZ: Double, atRest: Boolean, magneticDisturbance: Boolean, accelerometerRejected: Boolean)

    /** A marker the user set at [timestampNs] (sensor clock) with [label] (may be empty; the format cuts it to one short line). */
    @Throws(IOException::class)
    fun marker(timestampNs: Long, label: String)

    /**
     * A whole clock exchange with the laptop clock [laptopClock] while linked (docs/SYNC.md): into clock.csv, the first
     * naming the session's clock_link; another laptop's are left out.
     */
    @Throws(IOException::class)
    fun clockExchange(e: ClockExchange, laptopClock: String) = Unit

    /** Hands every row so far to the operating system, so a killed process loses none of them. */
    @Throws(IOException::class)
    fun flush()

    /**
     * Once a minute or so: adds a wall-clock [anchor] (wall-clock adjustments show up between
     * anchors) and forces every row to the storage device (fsync: survives power loss).
     */
    @Throws(IOException::class)
    fun checkpoint(anchor: ClockAnchor)

    /** Completes the session (summary, end reason) and closes it. */
    @Throws(IOException::class)
    fun finish(end: RecordingEnd)

    /**
     * After a failure: hands what it can to the storage, records why ([end]) if it still can,
     * and closes the files without completing the session (it is repaired by recovery); never throws.
     */
    fun abandon(end: RecordingEnd)
}

/** Why a recording ended. */
internal sealed interface RecordingEnd {
    /** The user (or the notification's Stop action) stopped it. */
    data object Stopped : RecordingEnd

    /** The maximum duration of the settings ([RecordingLimits.maxDurationS]) was reached. */
    data class MaxDuration(val seconds: Long) : RecordingEnd

    /** The battery fell to the settings' stop level ([RecordingLimits.stopBatteryPercent]) while not charging. */
    data class BatteryLow(val percent: Int) : RecordingEnd

    /** The queue between sensors and writer filled up: storage could not keep up. */
    data class QueueOverflow(val atTimestampNs: Long) : RecordingEnd

    /** Free space fell below the recorder's margin; stopped before the disk was full. */
    data class StorageLow(val freeBytes: Long) : RecordingEnd

    /** Writing failed. */
    data class WriteFailed(val message: String) : RecordingEnd

    /** True when the recording ended by something else than the user or a limit the user set. */
    val isFailure: Boolean get() = this !is Stopped && this !is MaxDuration && this !is BatteryLow

    /** The `end_reason` of meta.json (docs/SESSION_FORMAT.md). */
    val reason: String
        get() = when (this) {
            Stopped -> "stopped"
            is MaxDuration -> "max_duration"
            is BatteryLow -> "battery_low"
            is QueueOverflow -> "queue_overflow"
            is StorageLow -> "storage_low"
            is WriteFailed -> "write_failed: $message"
        }
}
