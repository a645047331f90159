/*
 * The export formats' writers (docs/EXPORT.md), fed the steps of a replay by [Exports]: EuRoC's ASL
 * folder, Kalibr's imu0.csv and imu.yaml, Gyroflow's gcsv 1.3 (and ROS 2 MCAP in Ros2Writer.kt).
 * Frames: readings in Android's device axes (x right, y up, z out of the screen; an iOS export is
 * turned into them on import), the orientation [w, x, y, z] sensor → ENU (east, magnetic north, up),
 * or ENU turned about up by a heading tare; docs/CONVENTIONS.md.
 */
package dev.motionfusion.core.export

import dev.motionfusion.core.event.SensorEvents
import dev.motionfusion.core.event.SampleRate
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.input.Recording
import dev.motionfusion.core.io.AsciiNumbers
import dev.motionfusion.core.replay.ReplayStep
import java.io.BufferedOutputStream
import java.io.Closeable
import java.io.OutputStream
import java.nio.charset.StandardCharsets
import java.nio.file.Files
import java.nio.file.Path
import java.util.Locale

/** What every export says about where it came from and its frames. */
internal class About(
    rec: Recording, generator: String, mode: String, offline: Boolean, calibrated: Boolean, val world: String = WORLD, shiftNs: Long = 0L,
) {
    val source = "$generator from ${rec.format.description} ${rec.name}"
    val device = rec.metadata?.device?.let { "${it.manufacturer} ${it.model}".trim() }?.takeIf { it.isNotEmpty() }
    val filter = "Madgwick ${if (mode == "IMU") "6D" else "9D"}${if (offline) " offline" else ""}${if (calibrated) ", calibrated readings" else ""}"

    /** The clock of the times written: the recording's own, or that moved later by [shiftNs] (Exports.clockShift). */
    val time = if (shiftNs == 0L) TIME else "the recording's own clock + ${shiftNs / 1_000_000_000L} s (it starts before 0), ns"

    companion object {
        const val AXES = "Android device axes: x right, y up (top edge), z out of the screen; right-handed"
        const val WORLD = "ENU: x east, y magnetic north, z up"
        const val WORLD_6D = "ENU turned about up by an unknown heading (6D, no magnetometer: no north): x, y horizontal, z up"
        const val QUATERNION = "[w, x, y, z] Hamilton, rotating sensor (device) vectors into the world frame"
        const val TIME = "the recording's own clock, ns"
    }
}

/** One export format: fed the replay's steps and the magnetometer's own readings. */
internal abstract class ExportWriter : Closeable {
    var imuRows = 0L
        protected set
    var orientationRows = 0L
        protected set
    var magnetometerRows = 0L
        protected set
    private val rows = SampleRate()

    /** One replay step (a gyroscope sample). */
    abstract fun step(step: ReplayStep)

    /** A magnetometer reading at its own time (ignored by formats without a magnetometer file). */
    open fun magnetometer(timestampNs: Long, values: DoubleArray) {}

    /** After the last step: the files that need the whole recording (rates). */
    open fun finish() {}

    protected fun counted(t: Long) {
        rows.add(t)
        imuRows++
    }

    /** Rate of the IMU rows, Hz, gaps left out (SampleRate; NaN with fewer than two). */
    protected fun rateHz(): Double = rows.hz

    protected fun rate(): String = rateHz().let { if (it.isFinite()) String.format(Locale.ROOT, "%.3f", it) else ".nan" }
}

/** A CSV written row by row with the project's number formats: readings as the shortest decimal of their float, quaternions to 9 decimals. */
internal class CsvFile(stream: OutputStream) : Closeable {
    private val out = BufferedOutputStream(stream, 1 shl 16)
    private val buf = ByteArray(512)
    private var p = 0

    constructor(path: Path) : this(Files.newOutputStream(path))

    fun line(text: String) = out.write((text + "\n").toByteArray(StandardCharsets.UTF_8))

    fun long(v: Long): CsvFile { sep(); p = AsciiNumbers.long(buf, p, v); return this }

    /** [v] ≥ 0 with leading zeros to at least [digits] digits. */
    fun padded(v: Long, digits: Int): CsvFile {
        require(v >= 0) { "padded: $v < 0" }
        sep()
        var n = 1
        var x = v
        while (x >= 10) { x /= 10; n++ }
        repeat(maxOf(0, digits - n)) { buf[p++] = '0'.code.toByte() }
        p = AsciiNumbers.long(buf, p, v)
        return this
    }
    fun floats(v: DoubleArray, n: Int = 3): CsvFile { for (k in 0 until n) { sep(); p = AsciiNumbers.float(buf, p, v[k].toFloat()) }; return this }
    fun fixed(v: Double, decimals: Int = 9): CsvFile { sep(); p = AsciiNumbers.fixed(buf, p, v, decimals); return this }

    /** [n] columns of 0: what a format requires and nothing estimated. */
    fun zeros(n: Int): CsvFile { repeat(n) { sep(); buf[p++] = '0'.code.toByte() }; return this }

    fun end() {
        buf[p++] = '\n'.code.toByte()
        out.write(buf, 0, p)
        p = 0
    }

    private fun sep() { if (p > 0) buf[p++] = ','.code.toByte() }

    override fun close() = out.close()
}

/** The events of a replay, each magnetometer reading also handed to [writer] at its own time as [time] writes it. */
internal class MagnetometerTee(private val events: SensorEvents, private val writer: ExportWriter, private val time: (Long) -> Long) : SensorEvents by events {
    override fun next(): Boolean {
        val more = events.next()
        if (more && events.stream == SessionStream.MAGNETOMETER) writer.magnetometer(time(events.timestampNs), events.values)
        return more
    }
}

/** EuRoC's ASL folder layout (mav0/…), written into [root]. */
internal class EurocWriter(root: Path, private val hasMagnetometer: Boolean, private val noise: NoiseModel?, private val about: About) : ExportWriter() {
    private val mav0 = root.resolve("mav0")
    private val imu: CsvFile
    private val pose: CsvFile
    private val mag: CsvFile?

    init {
        for (d in listOf("imu0", "state_groundtruth_estimate0") + if (hasMagnetometer) listOf("mag0") else emptyList()) Files.createDirectories(mav0.resolve(d))
        imu = CsvFile(mav0.resolve("imu0/data.csv"))
        imu.line(IMU_HEADER)
        pose = CsvFile(mav0.resolve("state_groundtruth_estimate0/data.csv"))
        pose.line(POSE_HEADER)
        mag = if (hasMagnetometer) CsvFile(mav0.resolve("mag0/data.csv")).also { it.line(MAG_HEADER) } else null
    }

    override fun step(step: ReplayStep) {
        if (step.specificForce[0].isNaN()) return
        counted(step.timestampNs)
        imu.long(step.timestampNs).floats(step.angularVelocity).floats(step.specificForce).end()
        if (step.initialised) {
            orientationRows++
            // Position, then after the orientation velocity and the two biases: not estimated, 0.
            pose.long(step.timestampNs).zeros(3)
            for (k in 0 until 4) pose.fixed(step.orientation[k])
            pose.zeros(9).end()
        }
    }

    override fun magnetometer(timestampNs: Long, values: DoubleArray) {
        val m = mag ?: return
        magnetometerRows++
        m.long(timestampNs).floats(values).end()
    }

    override fun finish() {
        write("imu0/sensor.yaml", buildString {
            appendLine("# ${about.source}${about.device?.let { " ($it)" } ?: ""}")
            appendLine("# Readings in $AXES_COMMENT; times: ${about.time}.")
            appendLine("sensor_type: imu")
            appendLine("comment: ${yamlString("phone IMU" + (about.device?.let { " of $it" } ?: "") + ": gyroscope (rad/s) and accelerometer (specific force, m/s^2) in Android device axes; one row per gyroscope sample, the accelerometer held")}")
            appendLine()
            appendLine("# The sensor is the body: T_BS is the identity.")
            appendIdentity()
            appendLine("rate_hz: ${rate()}  # rate of the rows, gaps left out")
            appendLine()
            if (noise == null) {
                appendLine("# No noise model known for this phone: run fusion allan on a still recording of it and")
                appendLine("# export with --noise IMU.yaml to have the four noise figures written here.")
            } else {
                appendLine("# Noise model (continuous time) from the --noise file (fusion allan's kalibr imu.yaml).")
                appendLine("gyroscope_noise_density: ${noise.figures.getValue("gyroscope_noise_density")}  # rad/s/sqrt(Hz)")
                appendLine("gyroscope_random_walk: ${noise.figures.getValue("gyroscope_random_walk")}  # rad/s^2/sqrt(Hz)")
                appendLine("accelerometer_noise_density: ${noise.figures.getValue("accelerometer_noise_density")}  # m/s^2/sqrt(Hz)")
                appendLine("accelerometer_random_walk: ${noise.figures.getValue("accelerometer_random_walk")}  # m/s^3/sqrt(Hz)")
                if (rateHz().isFinite()) append(NoiseConfigs.discreteComment(noise, rateHz()))
            }
        })
        write("state_groundtruth_estimate0/sensor.yaml", buildString {
            appendLine("# ${about.source}")
            appendLine("# NOT ground truth: the orientation estimated by the ${about.filter} filter of fusion replay")
            appendLine("# (the same options give the same rows). Position, velocity and the gyroscope and")
            appendLine("# accelerometer biases: not estimated, written as 0 (EuRoC's 17 columns, so its readers parse it).")
            appendLine("# q_RS: ${About.QUATERNION}; R is ${about.world}; S the device ($AXES_COMMENT).")
            appendLine("# Rows from the filter's first orientation on; times: ${about.time}.")
            appendLine("sensor_type: orientation_estimate")
            appendLine("comment: ${yamlString("fused orientation (${about.filter}), an estimate; position, velocity and biases 0")}")
            appendIdentity()
        })
        if (hasMagnetometer) {
            write("mag0/sensor.yaml", buildString {
                appendLine("# ${about.source}")
                appendLine("# Each magnetometer reading at its own time (${about.time}), µT, in $AXES_COMMENT.")
                appendLine("sensor_type: magnetometer")
                appendLine("comment: ${yamlString("phone magnetometer (calibrated field as the phone reports it, uT)")}")
                appendIdentity()
            })
        }
    }

    private fun StringBuilder.appendIdentity() {
        appendLine("T_BS:")
        appendLine("  cols: 4")
        appendLine("  rows: 4")
        appendLine("  data: [1.0, 0.0, 0.0, 0.0,")
        appendLine("         0.0, 1.0, 0.0, 0.0,")
        appendLine("         0.0, 0.0, 1.0, 0.0,")
        appendLine("         0.0, 0.0, 0.0, 1.0]")
    }

    private fun write(file: String, text: String) = Files.write(mav0.resolve(file), text.toByteArray(StandardCharsets.UTF_8))

    override fun close() {
        imu.use { pose.use { mag?.close() } }
    }

    companion object {
        const val IMU_HEADER = "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]"
        const val POSE_HEADER = "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z [], " +
            "v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], b_w_RS_S_x [rad s^-1], b_w_RS_S_y [rad s^-1], b_w_RS_S_z [rad s^-1], " +
            "b_a_RS_S_x [m s^-2], b_a_RS_S_y [m s^-2], b_a_RS_S_z [m s^-2]"
        const val MAG_HEADER = "#timestamp [ns],m_S_x [uT],m_S_y [uT],m_S_z [uT]"
        private const val AXES_COMMENT = About.AXES

        /** A YAML double-quoted scalar. */
        fun yamlString(s: String) = "\"" + s.replace("\\", "\\\\").replace("\"", "\\\"") + "\""
    }
}

/** Kalibr's imu0.csv and imu.yaml, written into [root]. */
internal class KalibrWriter(private val root: Path, private val noise: NoiseModel?, private val about: About) : ExportWriter() {
    private val imu = CsvFile(root.resolve("imu0.csv")).also { it.line(HEADER) }

    override fun step(step: ReplayStep) {
        if (step.specificForce[0].isNaN()) return
        counted(step.timestampNs)
        // At least ten digits: kalibr_bagcreater splits the string into seconds (all but the last nine) and ns (the
        // times are never negative: Exports.clockShift).
        imu.padded(step.timestampNs, 10).floats(step.angularVelocity).floats(step.specificForce).end()
    }

    override fun finish() {
        // The frames first (comments: kalibr reads the keys only); then the noise model of fusion allan as it
        // wrote it, else the keys kalibr needs besides it.
        val frames = buildString {
            appendLine("# ${about.source}")
            appendLine("# imu0.csv: omega (gyroscope, rad/s) and alpha (accelerometer, specific force, m/s^2) in the")
            appendLine("# ${About.AXES}; timestamp: ${about.time}.")
        }
        // kalibr turns the densities into per-sample noise at update_rate: the rate of these rows, not the still recording's.
        val rateLine = "update_rate: ${rate()}  # Hz, rate of imu0.csv, gaps left out"
        val text = frames + (noise?.let { withRate(it.text, rateLine) } ?: buildString {
            appendLine("# No noise model known for this phone: kalibr needs accelerometer_noise_density,")
            appendLine("# accelerometer_random_walk, gyroscope_noise_density and gyroscope_random_walk; run")
            appendLine("# fusion allan on a still recording of the phone and export with --noise IMU.yaml.")
            appendLine("rostopic: /imu0")
            appendLine(rateLine)
        })
        Files.write(root.resolve("imu.yaml"), text.toByteArray(StandardCharsets.UTF_8))
    }

    override fun close() = imu.close()

    companion object {
        const val HEADER = "timestamp,omega_x,omega_y,omega_z,alpha_x,alpha_y,alpha_z"

        /** The noise file's [text] with its top-level update_rate line replaced by [line] (added when it has none). */
        fun withRate(text: String, line: String): String {
            val lines = text.lines().dropLastWhile { it.isEmpty() }
            val i = lines.indexOfFirst { it.startsWith("update_rate:") }
            val out = if (i < 0) lines + line else lines.toMutableList().also { it[i] = line }
            return out.joinToString("\n", postfix = "\n")
        }
    }
}

/** Gyroflow's gcsv 1.3: values in SI units with scales that turn them into Gyroflow's (s, rad/s, g, gauss). */
internal class GcsvWriter(stream: OutputStream, private val hasMagnetometer: Boolean, about: About) : ExportWriter() {
    private val out = CsvFile(stream)

    init {
        out.line("GYROFLOW IMU LOG")
        out.line("version,1.3")
        out.line("id,${field(about.device ?: "phone")}")
        // The phone's own axes, as Gyroflow takes a phone's (no axis swapped or negated).
        out.line("orientation,XYZ")
        out.line("note,${field("${about.source}; axes: ${About.AXES}; t: ${about.time}")}")
        out.line("vendor,motion_fusion")
        out.line("tscale,0.000000001")
        out.line("gscale,1")
        out.line("ascale,${1.0 / STANDARD_GRAVITY}")
        if (hasMagnetometer) out.line("mscale,0.01")
        out.line(if (hasMagnetometer) "t,gx,gy,gz,ax,ay,az,mx,my,mz" else "t,gx,gy,gz,ax,ay,az")
    }

    override fun step(step: ReplayStep) {
        if (step.specificForce[0].isNaN() || (hasMagnetometer && step.magneticField[0].isNaN())) return
        counted(step.timestampNs)
        out.long(step.timestampNs).floats(step.angularVelocity).floats(step.specificForce)
        if (hasMagnetometer) out.floats(step.magneticField)
        out.end()
    }

    override fun close() = out.close()

    private companion object {
        const val STANDARD_GRAVITY = 9.80665

        /** A header value: no comma (the reader splits on it), no line break. */
        fun field(s: String) = s.replace(',', ';').replace('\n', ' ').replace('\r', ' ')
    }
}
