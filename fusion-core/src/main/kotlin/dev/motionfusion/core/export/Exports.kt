/*
 * A recording in the layout another tool reads (docs/EXPORT.md): one mechanism for `fusion export`
 * and the app's Share/Save. The samples are those the replay steps on (one row per gyroscope
 * sample, the accelerometer and magnetometer held at that instant, as `fusion replay --rows`), the
 * orientation that of the same replay with the same settings.
 */
package dev.motionfusion.core.export

import dev.motionfusion.core.calib.Calibration
import dev.motionfusion.core.calib.CalibratedEvents
import dev.motionfusion.core.event.SampleRate
import dev.motionfusion.core.event.SensorEvents
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.filter.offline.OfflineSettings
import dev.motionfusion.core.input.Recording
import dev.motionfusion.core.io.ZipFolder
import dev.motionfusion.core.replay.HeadingTare
import dev.motionfusion.core.replay.HeadingTareSpec
import dev.motionfusion.core.replay.ReplayCounts
import dev.motionfusion.core.replay.ReplayListener
import dev.motionfusion.core.replay.ReplayStep
import dev.motionfusion.core.replay.Replayer
import java.io.OutputStream
import java.nio.file.Files
import java.nio.file.Path

/** The export formats; [folder]: written as a folder (zipped by [Exports.writeZip]), else as one file with the extension [extension]. */
public enum class ExportFormat(public val key: String, public val folder: Boolean, public val extension: String) {
    /** EuRoC's ASL folder: mav0/imu0, mav0/mag0, mav0/state_groundtruth_estimate0. */
    EUROC("euroc", true, "zip"),

    /** Kalibr's imu0.csv and imu.yaml. */
    KALIBR("kalibr", true, "zip"),

    /** Gyroflow's gcsv 1.3. */
    GCSV("gcsv", false, "gcsv"),

    /** ROS 2 MCAP (CDR), sensor_msgs/msg/Imu and MagneticField. */
    ROS2("ros2", false, "mcap"),
    ;

    public companion object {
        /** The format called [key] (euroc, kalibr, gcsv, ros2), null for none. */
        @JvmStatic
        public fun of(key: String): ExportFormat? = entries.firstOrNull { it.key == key.lowercase() }
    }
}

/**
 * How a recording is exported: the filter's [settings], the [calibration] applied to its readings, the
 * [offline] (two-pass) estimate, the phone's [noise] model (EuRoC's sensor.yaml, Kalibr's imu.yaml, the
 * ROS 2 covariances), a heading tare ([heading]) and what the outputs name as their maker ([generator],
 * e.g. "fusion export 1.0").
 */
public class ExportOptions @JvmOverloads constructor(
    public val settings: FilterSettings = FilterSettings(),
    public val calibration: Calibration? = null,
    public val offline: OfflineSettings? = null,
    public val noise: NoiseModel? = null,
    public val heading: HeadingTareSpec? = null,
    public val generator: String = "Motion Fusion",
)

/**
 * What an export wrote: IMU rows (one per gyroscope sample with an accelerometer reading before it),
 * orientation rows (EuRoC, ROS 2), magnetometer rows (EuRoC, ROS 2), the replay's [counts], the heading
 * tare applied (radians; null without one), the world frame the outputs name, and how far the times written
 * were moved from the recording's own clock ([clockShiftNs], whole seconds in ns; 0 unless it starts before 0).
 */
public class ExportResult internal constructor(
    public val imuRows: Long,
    public val orientationRows: Long,
    public val magnetometerRows: Long,
    public val counts: ReplayCounts,
    public val headingOffsetRad: Double?,
    public val world: String,
    public val clockShiftNs: Long,
)

/** Writes recordings in the export formats (docs/EXPORT.md). */
public object Exports {
    /**
     * Writes [rec] as [format] (EUROC or KALIBR) into the existing, empty [folder]. [progress] gets the events
     * read so far (as [Replayer.run]); an exception it throws stops the export. The caller removes a
     * folder left by a failure.
     * @throws dev.motionfusion.core.io.DataFormatException when [rec] is malformed or has nothing to export.
     */
    @JvmStatic
    @JvmOverloads
    public fun writeFolder(rec: Recording, format: ExportFormat, folder: Path, options: ExportOptions = ExportOptions(), progress: ((Long) -> Unit)? = null): ExportResult {
        require(format.folder) { "$format is written as a file: writeFile" }
        return export(rec, format, options, progress) { about, noise, _ ->
            if (format == ExportFormat.EUROC) EurocWriter(folder, rec.hasMagnetometer, noise, about) else KalibrWriter(folder, noise, about)
        }
    }

    /**
     * Writes [rec] as [format] (GCSV or ROS2) to [out], which it closes. As [writeFolder] otherwise.
     */
    @JvmStatic
    @JvmOverloads
    public fun writeFile(rec: Recording, format: ExportFormat, out: OutputStream, options: ExportOptions = ExportOptions(), progress: ((Long) -> Unit)? = null): ExportResult {
        require(!format.folder) { "$format is written as a folder: writeFolder or writeZip" }
        return export(rec, format, options, progress) { about, noise, rateHz ->
            val magnetometer = rec.hasMagnetometer
            if (format == ExportFormat.GCSV) GcsvWriter(out, magnetometer, about) else Ros2Writer(out, magnetometer, about, noise, rateHz)
        }
    }

    /**
     * Writes [rec] as [format] to [out] as one file: a folder format zipped (its files inside the folder
     * [name], written first into a folder under [scratch] that is removed again), a file format as it is.
     * Does not close [out].
     */
    @JvmStatic
    @JvmOverloads
    public fun writeZip(rec: Recording, format: ExportFormat, out: OutputStream, name: String, scratch: Path, options: ExportOptions = ExportOptions(), progress: ((Long) -> Unit)? = null): ExportResult {
        if (!format.folder) return writeFile(rec, format, NotClosing(out), options, progress)
        val folder = Files.createTempDirectory(scratch, ".export-")
        try {
            val result = writeFolder(rec, format, folder, options, progress)
            ZipFolder.write(folder, name, out)
            return result
        } finally {
            ZipFolder.removeTree(folder)
        }
    }

    /** Rate of the gyroscope samples of [rec], Hz (the rate of the IMU rows, SampleRate; NaN with fewer than two). */
    private fun gyroscopeRate(rec: Recording): Double = rec.events(setOf(SessionStream.GYROSCOPE)).use { e ->
        val meter = SampleRate()
        while (e.next()) if (e.stream == SessionStream.GYROSCOPE) meter.add(e.timestampNs)
        meter.hz
    }

    private fun export(
        rec: Recording, format: ExportFormat, options: ExportOptions, progress: ((Long) -> Unit)?,
        writer: (About, NoiseModel?, Double) -> ExportWriter,
    ): ExportResult {
        val settings = options.settings
        // A heading tare is known before anything is written (a first replay finds the heading at its moment), so the metadata can name the frame.
        val tareRad = options.heading?.offsetRad(rec.name) { probe -> replay(rec, options, probe, null, null) }
        val world = when {
            options.heading != null && tareRad != null -> options.heading.describe(Math.toDegrees(tareRad))
            settings.mode == FilterMode.IMU -> About.WORLD_6D
            else -> About.WORLD
        }
        val shift = clockShift(rec)
        val about = About(rec, options.generator, settings.mode.name, options.offline != null, options.calibration != null, world, shift)
        // The ROS 2 covariances need the rate before the first message: the gyroscope's, from a first pass.
        val rate = if (format == ExportFormat.ROS2 && options.noise != null) gyroscopeRate(rec) else Double.NaN
        val w = writer(about, options.noise, rate)
        val counts = w.use {
            val plain = object : ReplayListener {
                override fun step(step: ReplayStep) {
                    val t = step.timestampNs
                    step.timestampNs = shifted(rec, t, shift)
                    w.step(step)
                    step.timestampNs = t
                }
            }
            val listener = tareRad?.let { HeadingTare.offset(plain, it) } ?: plain
            replay(rec, options, listener, progress, w, shift).also { w.finish() }
        }
        fun nothing(reason: String): Nothing = throw dev.motionfusion.core.io.DataFormatException(rec.name, 0, 0, reason)
        if (counts.gyroscope == 0L) nothing("no gyroscope samples: nothing to export")
        if (w.imuRows == 0L) {
            nothing("no gyroscope sample after the first accelerometer${if (format == ExportFormat.GCSV && rec.hasMagnetometer) " and magnetometer" else ""} reading: nothing to export")
        }
        return ExportResult(w.imuRows, w.orientationRows, w.magnetometerRows, counts, tareRad, world, shift)
    }

    /**
     * How far [rec]'s times are moved for the export: 0, or for a recording whose clock starts before 0 (a
     * phyphox export's first samples can come before its t = 0) the whole seconds that bring its first event to 0
     * or after, since ROS 2's times and Kalibr's are unsigned and EuRoC's are never negative.
     */
    private fun clockShift(rec: Recording): Long {
        val first = rec.events().use { e -> if (e.next()) e.timestampNs else 0L }
        if (first >= 0L) return 0L
        val seconds = (first / -NS_PER_S) + (if (first % NS_PER_S != 0L) 1 else 0)
        if (seconds > Long.MAX_VALUE / NS_PER_S / 2) {
            throw dev.motionfusion.core.io.DataFormatException(rec.name, 0, 0, "times start ${-first / NS_PER_S} s before 0: too far to move onto the export's unsigned clock")
        }
        return seconds * NS_PER_S
    }

    private const val NS_PER_S = 1_000_000_000L

    /**
     * [t] moved by [shift] as written: never negative (a step back to before the first event, which the replay
     * lets pass under a second, would be one) and never wrapped round.
     */
    private fun shifted(rec: Recording, t: Long, shift: Long): Long {
        val s = try {
            Math.addExact(t, shift)
        } catch (_: ArithmeticException) {
            throw dev.motionfusion.core.io.DataFormatException(rec.name, 0, 0, "a time of ${t / NS_PER_S} s is beyond what the export's clock holds")
        }
        if (s < 0) {
            throw dev.motionfusion.core.io.DataFormatException(rec.name, 0, 0,
                "a time ${(-s).toDouble() / NS_PER_S} s before the recording's first event (a step back in time): the export's times cannot be negative; sort the recording by time")
        }
        return s
    }

    /** One replay of [rec] into [listener], each magnetometer reading also handed to [tee] at its own time (moved by [shiftNs]). */
    private fun replay(rec: Recording, options: ExportOptions, listener: ReplayListener, progress: ((Long) -> Unit)?, tee: ExportWriter?, shiftNs: Long = 0L): ReplayCounts {
        val replayer = Replayer(options.settings)
        val raw = rec.events()
        val calibrated: SensorEvents = options.calibration?.let { CalibratedEvents(raw, it, rec.streams) } ?: raw
        return (if (tee == null) calibrated else MagnetometerTee(calibrated, tee) { t -> shifted(rec, t, shiftNs) }).use { e ->
            if (options.offline == null) replayer.run(e, rec.originNs, listener, progress, rec.name)
            else replayer.runOffline(e, rec.originNs, listener, progress, rec.name, options.offline)
        }
    }

    /** [out] with close() only flushing. */
    private class NotClosing(private val out: OutputStream) : OutputStream() {
        override fun write(b: Int) = out.write(b)
        override fun write(b: ByteArray, off: Int, len: Int) = out.write(b, off, len)
        override fun flush() = out.flush()
        override fun close() = out.flush()
    }
}
