/*
 * The streaming writer of a session folder (docs/SESSION_FORMAT.md), built for the app's hot
 * path: one writer thread hands it samples it has already copied out of SensorEvent; each call
 * formats one CSV row into that stream's byte buffer (no String, no String.format, no boxing,
 * locale-independent) and the buffer goes to the file when full or on flush().
 *
 * Durability: flush() hands buffered rows to the operating system, so they survive the process
 * being killed; call it at least once a second. sync() also forces them to the storage device
 * (survives power loss); it is slow, call it rarely (anchor() does it, e.g. every minute). A
 * killed process leaves at most a partial last line per file and meta.json with
 * "complete": false: SessionRecovery.recover repairs that. meta.json is only ever replaced
 * whole (AtomicFiles: temporary file, sync, rename, folder sync), and "complete": true is
 * written only after every stream has been synced.
 *
 * Units and frames are those of SessionStream: SI, Android device frame, ENU quaternions.
 */
package dev.motionfusion.core.session

import dev.motionfusion.core.sync.ClockExchange

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.io.AsciiNumbers
import dev.motionfusion.core.io.AtomicFiles
import dev.motionfusion.core.io.FileOperations
import java.io.Closeable
import java.io.Flushable
import java.io.IOException
import java.nio.charset.StandardCharsets
import java.nio.file.Files
import java.nio.file.Path

/**
 * Writes one session into a folder: a CSV file per stream (created at the stream's first
 * sample) and meta.json. Not thread-safe: call every method from one thread.
 */
public class SessionWriter private constructor(
    /** The session folder. */
    public val directory: Path,
    initial: SessionMetadata,
    private val bufferBytes: Int,
    private val files: FileOperations,
) : Closeable, Flushable {

    private val atomic = AtomicFiles(files)

    private val outs = arrayOfNulls<StreamOut>(SessionStream.entries.size)
    private var markers: StreamOut? = null
    private var clock: StreamOut? = null
    private var meta = initial.copy(formatVersion = SessionMetadata.FORMAT_VERSION, complete = false)
    private var closed = false
    private var lastTimestampNs = Long.MIN_VALUE

    /** The metadata as it stands (stream statistics are filled in by [close]). */
    public val metadata: SessionMetadata get() = meta

    init {
        writeMetadata()
    }

    /** TYPE_ACCELEROMETER sample: m/s², device frame; [accuracy] = SensorEvent.accuracy. */
    public fun accelerometer(timestampNs: Long, x: Float, y: Float, z: Float, accuracy: Int): Unit =
        row3(SessionStream.ACCELEROMETER, timestampNs, x, y, z, accuracy)

    /** TYPE_GYROSCOPE sample: rad/s, device frame. */
    public fun gyroscope(timestampNs: Long, x: Float, y: Float, z: Float, accuracy: Int): Unit =
        row3(SessionStream.GYROSCOPE, timestampNs, x, y, z, accuracy)

    /** TYPE_MAGNETIC_FIELD sample: µT, device frame. */
    public fun magnetometer(timestampNs: Long, x: Float, y: Float, z: Float, accuracy: Int): Unit =
        row3(SessionStream.MAGNETOMETER, timestampNs, x, y, z, accuracy)

    /** TYPE_GYROSCOPE_UNCALIBRATED sample: rate and estimated drift, rad/s. */
    public fun gyroscopeUncalibrated(
        timestampNs: Long, x: Float, y: Float, z: Float, biasX: Float, biasY: Float, biasZ: Float, accuracy: Int,
    ) {
        val o = begin(SessionStream.GYROSCOPE_UNCALIBRATED, timestampNs)
        o.float(x); o.float(y); o.float(z); o.float(biasX); o.float(biasY); o.float(biasZ)
        o.end(accuracy)
    }

    /** TYPE_MAGNETIC_FIELD_UNCALIBRATED sample: field and hard-iron bias, µT. */
    public fun magnetometerUncalibrated(
        timestampNs: Long, x: Float, y: Float, z: Float, biasX: Float, biasY: Float, biasZ: Float, accuracy: Int,
    ) {
        val o = begin(SessionStream.MAGNETOMETER_UNCALIBRATED, timestampNs)
        o.float(x); o.float(y); o.float(z); o.float(biasX); o.float(biasY); o.float(biasZ)
        o.end(accuracy)
    }

    /**
     * TYPE_ROTATION_VECTOR sample as Android's values: [x], [y], [z] = axis·sin(θ/2), [w] =
     * cos(θ/2) (device → ENU), [headingAccuracyRad] (−1 when unknown; NaN writes an empty field).
     */
    public fun rotationVector(timestampNs: Long, x: Float, y: Float, z: Float, w: Float, headingAccuracyRad: Float, accuracy: Int) {
        val o = begin(SessionStream.ROTATION_VECTOR, timestampNs)
        o.float(x); o.float(y); o.float(z); o.float(w)
        if (headingAccuracyRad.isNaN()) o.empty() else o.float(headingAccuracyRad)
        o.end(accuracy)
    }

    /** TYPE_GAME_ROTATION_VECTOR sample (x, y, z, w as [rotationVector]; arbitrary yaw). */
    public fun gameRotationVector(timestampNs: Long, x: Float, y: Float, z: Float, w: Float, accuracy: Int) {
        val o = begin(SessionStream.GAME_ROTATION_VECTOR, timestampNs)
        o.float(x); o.float(y); o.float(z); o.float(w)
        o.end(accuracy)
    }

    /** The live filter's orientation (sensor → ENU, [w, x, y, z]); stored with float precision. */
    public fun orientation(timestampNs: Long, qw: Double, qx: Double, qy: Double, qz: Double): Unit =
        quaternion(SessionStream.ORIENTATION, timestampNs, qw, qx, qy, qz)

    /** A known true orientation (sensor → ENU), for simulated or motion-captured sessions. */
    public fun truth(timestampNs: Long, qw: Double, qx: Double, qy: Double, qz: Double): Unit =
        quaternion(SessionStream.TRUTH, timestampNs, qw, qx, qy, qz)

    /** The live filter's diagnostics: gyroscope bias estimate (rad/s, device frame) and its flags. */
    public fun filterDiagnostics(
        timestampNs: Long, biasX: Double, biasY: Double, biasZ: Double,
        atRest: Boolean, magneticDisturbance: Boolean, accelerometerRejected: Boolean,
    ) {
        val o = begin(SessionStream.FILTER_DIAGNOSTICS, timestampNs)
        o.float(biasX.toFloat()); o.float(biasY.toFloat()); o.float(biasZ.toFloat())
        o.flag(atRest); o.flag(magneticDisturbance); o.flag(accelerometerRejected)
        o.end(NO_ACCURACY)
    }

    /**
     * Any stream from a copy of SensorEvent.values: the first [SessionStream.valueCount] of
     * [values] (missing trailing values, e.g. a rotation vector without heading accuracy, are
     * written as empty fields); [accuracy] ignored by streams without an accuracy column.
     */
    public fun write(stream: SessionStream, timestampNs: Long, values: FloatArray, accuracy: Int): Unit =
        write(stream, timestampNs, values, 0, values.size, accuracy)

    /**
     * As [write], from values[offset until offset + count] (e.g. a slot of a ring buffer); NaN
     * values are written as empty fields only for the rotation vector's heading accuracy.
     */
    public fun write(stream: SessionStream, timestampNs: Long, values: FloatArray, offset: Int, count: Int, accuracy: Int) {
        require(offset >= 0 && count >= 0 && offset + count <= values.size) { "bad range $offset+$count of ${values.size}" }
        val o = begin(stream, timestampNs)
        val n = stream.valueCount
        for (i in 0 until n) {
            val v = if (i < count) values[offset + i] else Float.NaN
            if (i < count && !(v.isNaN() && stream == SessionStream.ROTATION_VECTOR && i == 4)) o.float(v) else o.empty()
        }
        o.end(if (stream.hasAccuracy) accuracy else NO_ACCURACY)
    }

    /**
     * A marker the user set at [timestampNs] (sensor clock) with [label] (may be empty), stored in
     * markers.csv as [SessionMarkers.label] makes it: one line, at most
     * [SessionMarkers.MAX_LABEL_CHARS] characters. Rare: this call may allocate.
     */
    public fun marker(timestampNs: Long, label: String) {
        checkOpen()
        val o = markers ?: StreamOut(SessionMarkers.FILE_NAME, SessionMarkers.HEADER, MARKER_BUFFER_BYTES).also { markers = it }
        o.bytes(timestampNs, SessionMarkers.row(timestampNs, SessionMarkers.label(label)))
    }

    /**
     * A whole clock exchange [e] with the laptop clock named [laptopClock] (docs/SYNC.md), one row of clock.csv
     * ([SessionClock]). The first names the session's `clock_link` (meta.json is rewritten then); an exchange with another
     * laptop clock is not written (a session holds one link): false then. Rare: this call may allocate.
     */
    public fun clockExchange(e: ClockExchange, laptopClock: String): Boolean {
        checkOpen()
        when (meta.clockLink) {
            null -> {
                meta = meta.copy(clockLink = laptopClock)
                writeMetadata()
            }
            laptopClock -> Unit
            else -> return false
        }
        val o = clock ?: StreamOut(SessionClock.FILE_NAME, SessionClock.HEADER, MARKER_BUFFER_BYTES).also { clock = it }
        o.bytes(e.t2, SessionClock.row(e).toByteArray(StandardCharsets.US_ASCII))
        return true
    }

    /** Records that recording paused at [elapsedRealtimeNs] (sensor clock); rewrites meta.json. */
    public fun pause(elapsedRealtimeNs: Long) {
        checkOpen()
        meta = meta.copy(pauses = meta.pauses + Pause(elapsedRealtimeNs, null))
        writeMetadata()
    }

    /** Records that recording resumed at [elapsedRealtimeNs]; rewrites meta.json. */
    public fun resume(elapsedRealtimeNs: Long) {
        checkOpen()
        val last = meta.pauses.lastOrNull()
        check(last != null && last.endElapsedRealtimeNs == null) { "resume without pause" }
        meta = meta.copy(pauses = meta.pauses.dropLast(1) + last.copy(endElapsedRealtimeNs = elapsedRealtimeNs))
        writeMetadata()
    }

    /**
     * A checkpoint with a wall-clock anchor taken during recording (e.g. every minute): the
     * streams are synced to the device ([sync]), then meta.json with the anchor is replaced
     * atomically and synced.
     */
    public fun anchor(anchor: ClockAnchor) {
        sync()
        meta = meta.copy(anchors = meta.anchors + anchor)
        writeMetadata()
    }

    /** Replaces the metadata by [transform] of it (e.g. achieved settings known later); rewrites meta.json. */
    public fun updateMetadata(transform: (SessionMetadata) -> SessionMetadata) {
        checkOpen()
        meta = transform(meta).copy(formatVersion = SessionMetadata.FORMAT_VERSION, complete = false)
        writeMetadata()
    }

    /** Hands every buffered row to the operating system (survives a killed process). */
    override fun flush() {
        checkOpen()
        for (o in outs) o?.drain()
        markers?.drain()
        clock?.drain()
    }

    /** [flush], then forces the files to the storage device (survives power loss). Slow. */
    public fun sync() {
        flush()
        for (o in outs) o?.sync()
        markers?.sync()
        clock?.sync()
    }

    /** Closes with the end time set to the latest sample timestamp written. */
    override fun close() {
        if (closed) return
        close(if (lastTimestampNs == Long.MIN_VALUE) null else lastTimestampNs)
    }

    /**
     * Flushes, syncs and closes every stream, then writes the final meta.json (complete,
     * per-stream statistics, [endElapsedRealtimeNs], [endReason] such as "stopped" or
     * "storage_low"). When a stream cannot be written or synced, the session is not marked
     * complete (it is left for SessionRecovery, as after [abandon]) and the failure is thrown.
     * A second close does nothing.
     */
    @JvmOverloads
    public fun close(endElapsedRealtimeNs: Long?, endReason: String = "stopped") {
        if (closed) return
        var failure: IOException? = null
        for (o in outs + markers + clock) {
            try {
                o?.close(sync = true)
            } catch (e: IOException) {
                if (failure == null) failure = e else failure.addSuppressed(e)
            }
        }
        closed = true
        if (failure != null) throw failure
        val stats = SessionStream.entries.mapNotNull { s -> outs[s.ordinal]?.let { s to it.stats() } }.toMap()
        meta = meta.copy(complete = true, endElapsedRealtimeNs = endElapsedRealtimeNs, endReason = endReason, streams = stats, markers = markers?.stats())
        writeMetadata()
    }

    /**
     * After a failure (e.g. the disk is full): hands what it can to the OS and closes the files
     * without completing the session; never throws. meta.json keeps "complete": false, so the
     * session is recovered later like a killed one (SessionRecovery).
     */
    public fun abandon() {
        if (closed) return
        closed = true
        for (o in outs + markers + clock) {
            try {
                o?.close(sync = false)
            } catch (e: IOException) {
                // The storage failed; recovery keeps what reached it.
            }
        }
    }

    private fun row3(stream: SessionStream, t: Long, x: Float, y: Float, z: Float, accuracy: Int) {
        val o = begin(stream, t)
        o.float(x); o.float(y); o.float(z)
        o.end(accuracy)
    }

    private fun quaternion(stream: SessionStream, t: Long, w: Double, x: Double, y: Double, z: Double) {
        val o = begin(stream, t)
        o.float(w.toFloat()); o.float(x.toFloat()); o.float(y.toFloat()); o.float(z.toFloat())
        o.end(NO_ACCURACY)
    }

    private fun begin(stream: SessionStream, t: Long): StreamOut {
        checkOpen()
        val o = outs[stream.ordinal] ?: StreamOut(stream.fileName, stream.header, bufferBytes).also { outs[stream.ordinal] = it }
        o.begin(t)
        if (t > lastTimestampNs) lastTimestampNs = t
        return o
    }

    private fun checkOpen() = check(!closed) { "session writer closed" }

    private fun writeMetadata() =
        atomic.write(directory.resolve(SessionMetadata.FILE_NAME), MetadataJson.write(meta).toByteArray(StandardCharsets.UTF_8))

    /** One stream's file, byte buffer and running statistics. */
    private inner class StreamOut(fileName: String, header: String, bufferBytes: Int) {
        private val file = files.open(directory.resolve(fileName))
        private val buf = ByteArray(bufferBytes)
        private var pos = 0
        private val stats = StatsAccumulator()

        init {
            val h = (header + "\n").toByteArray(StandardCharsets.US_ASCII)
            h.copyInto(buf)
            pos = h.size
        }

        fun begin(t: Long) {
            if (pos + MAX_ROW_BYTES > buf.size) drain()
            pos = AsciiNumbers.long(buf, pos, t)
            stats.add(t)
        }

        /** A whole row already formatted (markers), counted at [t]. */
        fun bytes(t: Long, row: ByteArray) {
            if (pos + row.size > buf.size) drain()
            row.copyInto(buf, pos)
            pos += row.size
            stats.add(t)
        }

        fun float(v: Float) {
            buf[pos++] = COMMA
            pos = AsciiNumbers.float(buf, pos, v)
        }

        fun empty() {
            buf[pos++] = COMMA
        }

        fun flag(b: Boolean) {
            buf[pos++] = COMMA
            buf[pos++] = if (b) ONE else ZERO
        }

        fun end(accuracy: Int) {
            if (accuracy != NO_ACCURACY) {
                buf[pos++] = COMMA
                pos = AsciiNumbers.long(buf, pos, accuracy.toLong())
            }
            buf[pos++] = NEWLINE
        }

        fun drain() {
            if (pos > 0) {
                file.write(buf, 0, pos)
                pos = 0
            }
        }

        fun sync() = file.sync()

        fun close(sync: Boolean) {
            try {
                drain()
                if (sync) sync()
            } finally {
                file.close()
            }
        }

        fun stats(): StreamStats = stats.result()
    }

    public companion object {
        private const val COMMA = ','.code.toByte()
        private const val NEWLINE = '\n'.code.toByte()
        private const val ONE = '1'.code.toByte()
        private const val ZERO = '0'.code.toByte()
        private const val NO_ACCURACY = Int.MIN_VALUE

        /** Upper bound of one row: timestamp, 6 floats, accuracy, separators. */
        private const val MAX_ROW_BYTES = AsciiNumbers.MAX_LONG_CHARS + 8 * (AsciiNumbers.MAX_FLOAT_CHARS + 1) + 16

        /** Buffer of markers.csv: above its longest row (a label of 200 three-byte characters, about 630 bytes). */
        private const val MARKER_BUFFER_BYTES = 4096

        /** Default buffer per stream: 64 KiB (≈ 1,500 rows; a second at 1.5 kHz). */
        public const val DEFAULT_BUFFER_BYTES: Int = 1 shl 16

        /**
         * Starts a session in [directory] (created if missing; must not already hold a session)
         * and writes meta.json with [metadata] and "complete": false. Every file operation goes
         * through [files] (tests pass one that fails or stops at a chosen step).
         * @throws IllegalArgumentException when [directory] already holds a meta.json.
         */
        @JvmStatic
        @JvmOverloads
        public fun create(
            directory: Path,
            metadata: SessionMetadata,
            bufferBytes: Int = DEFAULT_BUFFER_BYTES,
            files: FileOperations = FileOperations.SYSTEM,
        ): SessionWriter {
            require(bufferBytes >= 4 * MAX_ROW_BYTES) { "bufferBytes must be ≥ ${4 * MAX_ROW_BYTES}" }
            Files.createDirectories(directory)
            require(!Files.exists(directory.resolve(SessionMetadata.FILE_NAME), java.nio.file.LinkOption.NOFOLLOW_LINKS)) { "$directory already holds a session" }
            return SessionWriter(directory, metadata, bufferBytes, files)
        }
    }
}

/**
 * Running statistics of a stream's timestamps: count, first, last, backwards and duplicate
 * steps, and mean and standard deviation of the intervals up to [MAX_INTERVAL_NS].
 */
internal class StatsAccumulator {
    private var count = 0L
    private var first = 0L
    private var last = 0L
    private var backwards = 0L
    private var duplicates = 0L
    private var intervals = 0L
    private var sum = 0.0
    private var sumSq = 0.0

    fun add(t: Long) {
        if (count > 0) {
            when {
                t < last -> backwards++
                t == last -> duplicates++
                // t > last here; the difference of two extreme timestamps overflows to a negative value.
                t - last in 1..MAX_INTERVAL_NS -> {
                    val s = (t - last) * 1e-9
                    intervals++
                    sum += s
                    sumSq += s * s
                }
            }
        } else {
            first = t
        }
        last = t
        count++
    }

    fun result(): StreamStats {
        val mean = if (intervals > 0) sum / intervals else Double.NaN
        val variance = if (intervals > 1) ((sumSq - sum * mean) / (intervals - 1)).coerceAtLeast(0.0) else Double.NaN
        return StreamStats(count, first, last, 1.0 / mean, kotlin.math.sqrt(variance) * 1e3, backwards, duplicates)
    }

    companion object {
        const val MAX_INTERVAL_NS = 1_000_000_000L
    }
}
