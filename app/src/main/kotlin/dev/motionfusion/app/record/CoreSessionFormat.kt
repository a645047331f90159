package dev.motionfusion.app.record

import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.app.sessions.CoreSessionRepair
import dev.motionfusion.core.session.SessionReader
import dev.motionfusion.core.session.SessionRecovery
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.SessionWriter
import java.io.File

/** The app's binding to the session format of `fusion-core` (docs/SESSION_FORMAT.md). */
internal object CoreSessionFormat : SessionFormat {
    override fun create(dir: File, metadata: SessionMetadata): SessionSink = CoreSessionSink(SessionWriter.create(dir.toPath(), metadata))

    override fun endNs(dir: File): Long? = SessionReader.open(dir.toPath()).use { it.metadata.endElapsedRealtimeNs }

    override fun isInterrupted(dir: File): Boolean = CoreSessionRepair.isInterrupted(dir)

    override fun recover(dir: File) = CoreSessionRepair.recover(dir)
}

/**
 * [SessionSink] on a [SessionWriter]: each raw row through the writer's typed, allocation-free
 * methods. After a failure the writer is abandoned, not closed (closing would write
 * "complete": true over files whose last rows never reached the disk): every stream that still
 * works is drained, the session stays interrupted and [SessionRecovery] repairs it from what is
 * on disk.
 */
internal class CoreSessionSink(private val writer: SessionWriter) : SessionSink {
    private var lastTimestampNs = Long.MIN_VALUE

    override fun raw(stream: SessionStream, timestampNs: Long, accuracy: Int, values: FloatArray, offset: Int) {
        val v = values
        val o = offset
        if (timestampNs > lastTimestampNs) lastTimestampNs = timestampNs
        when (stream) {
            SessionStream.ACCELEROMETER -> writer.accelerometer(timestampNs, v[o], v[o + 1], v[o + 2], accuracy)
            SessionStream.GYROSCOPE -> writer.gyroscope(timestampNs, v[o], v[o + 1], v[o + 2], accuracy)
            SessionStream.MAGNETOMETER -> writer.magnetometer(timestampNs, v[o], v[o + 1], v[o + 2], accuracy)
            SessionStream.GYROSCOPE_UNCALIBRATED ->
                writer.gyroscopeUncalibrated(timestampNs, v[o], v[o + 1], v[o + 2], v[o + 3], v[o + 4], v[o + 5], accuracy)
            SessionStream.MAGNETOMETER_UNCALIBRATED ->
                writer.magnetometerUncalibrated(timestampNs, v[o], v[o + 1], v[o + 2], v[o + 3], v[o + 4], v[o + 5], accuracy)
            SessionStream.ROTATION_VECTOR -> writer.rotationVector(timestampNs, v[o], v[o + 1], v[o + 2], v[o + 3], v[o + 4], accuracy)
            SessionStream.GAME_ROTATION_VECTOR -> writer.gameRotationVector(timestampNs, v[o], v[o + 1], v[o + 2], v[o + 3], accuracy)
            SessionStream.ACCELEROMETER_UNCALIBRATED -> writer.write(stream, timestampNs, v, o, stream.valueCount, accuracy)
            else -> throw IllegalArgumentException("$stream is not a sensor stream")
        }
    }

    override fun fused(timestampNs: Long, q: DoubleArray, offset: Int) =
        writer.orientation(timestampNs, q[offset], q[offset + 1], q[offset + 2], q[offset + 3])

    override fun diagnostics(
        timestampNs: Long, biasX: Double, biasY: Double, biasZ: Double,
        atRest: Boolean, magneticDisturbance: Boolean, accelerometerRejected: Boolean,
    ) = writer.filterDiagnostics(timestampNs, biasX, biasY, biasZ, atRest, magneticDisturbance, accelerometerRejected)

    override fun marker(timestampNs: Long, label: String) = writer.marker(timestampNs, label)

    override fun clockExchange(e: dev.motionfusion.core.sync.ClockExchange, laptopClock: String) {
        writer.clockExchange(e, laptopClock)
    }

    override fun flush() = writer.flush()

    /** [SessionWriter.anchor] syncs every stream before it replaces meta.json. */
    override fun checkpoint(anchor: ClockAnchor) = writer.anchor(anchor)

    override fun finish(end: RecordingEnd) =
        writer.close(if (lastTimestampNs == Long.MIN_VALUE) null else lastTimestampNs, end.reason)

    override fun abandon(end: RecordingEnd) {
        try {
            writer.updateMetadata { it.copy(endReason = end.reason) }
        } catch (_: Exception) {
            // The disk may not take even meta.json; recovery then says "interrupted".
        }
        writer.abandon()
    }
}
