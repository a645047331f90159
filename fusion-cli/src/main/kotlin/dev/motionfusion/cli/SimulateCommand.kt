package dev.motionfusion.cli

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.io.AsciiNumbers
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.DeviceInfo
import dev.motionfusion.core.session.SensorInfo
import dev.motionfusion.core.session.SessionArchive
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.SessionWriter
import dev.motionfusion.core.calib.Matrix3
import dev.motionfusion.core.sim.CalibrationMotion
import dev.motionfusion.core.sim.MagneticDisturbance
import dev.motionfusion.core.sim.MagneticDisturbanceKind
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulatedSample
import dev.motionfusion.core.sim.SimulationSettings
import dev.motionfusion.core.sim.TimeWindow
import dev.motionfusion.core.sim.ViolentMotion
import dev.motionfusion.core.sim.ViolentMotionKind
import java.io.BufferedOutputStream
import java.io.PrintStream
import java.nio.file.Files
import java.nio.file.Path
import java.nio.file.Paths
import java.util.Random
import java.util.zip.GZIPOutputStream

/** `fusion simulate -o OUT`: a session (or IMU table) from the project's MotionSimulator. */
internal class SimulateCommand(private val outputs: Outputs) : Command {
    override val name = "simulate"
    override val summary = "write a simulated recording (a session, with its truth; or an IMU table)"
    override val help = """
        |Usage: fusion simulate -o OUT [--duration S] [--rate HZ] [--seed N] [--motion calibration]
        |                       [sensor errors]
        |
        |Runs the project's MotionSimulator (seeded: the same options give the same data) and
        |writes what a phone would have recorded, values rounded to float like SensorEvent:
        |  OUT ending in .csv or .csv.gz: a plain IMU table t_s,gx,gy,gz,ax,ay,az,mx,my,mz (the
        |    sensors only: a table has no place for the truth; a session has)
        |  OUT ending in .zip: a session zip; otherwise a session folder, with
        |    accelerometer, gyroscope, magnetometer (same instants), truth.csv (the true
        |    orientation) and rotation_vector.csv at a quarter of the rate: a stand-in for the
        |    phone's own fusion, the truth with a 2° heading offset and 0.3° noise.
        |
        |Motion: smooth random rotation (1 rad/s per axis), at rest for the first and last
        |2 s; gyroscope bias (0.01, −0.02, 0.015) rad/s; noise 0.002 rad/s, 0.03 m/s², 0.3 µT;
        |field 48 µT, dip 60°; timestamps with 0.2 ms jitter.
        |
        |Options:
        |  -o, --output OUT     required
        |  --duration S         seconds (default 20)
        |  --rate HZ            sample rate (default 100)
        |  --seed N             random seed (default 8)
        |  --motion calibration a calibration recording instead (docs/CALIBRATION.md): still on
        |                       each of the six faces (1.5 s turning onto it, 4 s still), then turning
        |                       at up to 2.5 rad/s for the rest of --duration (default 100 s)
        |
        |Sensor errors (device frame; vectors as X,Y,Z, matrices as XX,YY,ZZ,XY,XZ,YZ of a
        |symmetric matrix or XX,YY,ZZ for a diagonal one):
        |  --hard-iron X,Y,Z          magnetometer offset, µT (default none)
        |  --soft-iron M              magnetometer soft iron K: mag = K·field + hard iron
        |  --gyro-bias X,Y,Z          gyroscope bias, rad/s (default 0.01,-0.02,0.015)
        |  --acc-offset X,Y,Z         accelerometer offset, m/s² (default none)
        |  --acc-scale M              accelerometer scale and misalignment M: acc = M·f + offset
        |  --gyro-noise-density N     white gyroscope noise, rad/s/√Hz, added to the 0.002 rad/s
        |  --acc-noise-density N      white accelerometer noise, m/s²/√Hz, added to the 0.03 m/s²
        |  --mag-noise SIGMA          magnetometer noise per sample, µT (default 0.3)
        |  --hard-iron-window S,E     the hard iron only from S to E s (a magnet or steel passing by)
        |  --field UT,DIP             the earth's field: strength in µT and dip in degrees (default
        |                             48,60; a steel hall can be 15,30)
        |
        |Violent motion and the sensors' limits (docs/ACCURACY.md, "Recovery after violent motion"):
        |  --violent KIND@S,...       drop, fall, shake or throw starting at S s (e.g. drop@5,shake@12);
        |                             the phone then lies still outside these motions, so what
        |                             follows each one shows how fast a filter comes back
        |  --acc-range M_S2           accelerometer clipped at ±M_S2 per axis (e.g. 78.5 for ±8 g)
        |  --gyro-range RAD_S         gyroscope clipped at ±RAD_S per axis (e.g. 34.9 for ±2000°/s)
        |  --gyro-scale-error R       gyroscope reads (1 + R) times the rate (e.g. 0.03)
        |  --mag-disturbance KIND@S:D,...  a magnetic disturbance from S s for D s (D ≥ 2): ferrous (an
        |                             object passing, up to 40 µT added) or hall (a weak 15 µT field,
        |                             dip 30°, pointing 40° west of north), e.g. ferrous@10:6,hall@30:20
        |""".trimMargin()

    override fun run(args: List<String>, out: PrintStream): Int {
        val o = Options(args, setOf("-o", "--output", "--duration", "--rate", "--seed", "--motion") + ERROR_OPTIONS, emptySet())
        if (o.positional.isNotEmpty()) throw UsageException("unexpected argument '${o.positional[0]}'")
        val output = o.value("-o") ?: o.value("--output") ?: throw UsageException("simulate needs -o OUT")
        val calibrationMotion = when (val m = o.value("--motion")) {
            null -> false
            "calibration" -> true
            else -> throw UsageException("--motion must be 'calibration', got '$m'")
        }
        val duration = o.double("--duration") ?: if (calibrationMotion) 100.0 else 20.0
        val rate = o.double("--rate") ?: 100.0
        val seed = o.long("--seed") ?: 8L
        if (duration <= 4.0 || duration > 86_400.0) throw UsageException("--duration must be in (4, 86400] s")
        if (rate < 10.0 || rate > 2000.0) throw UsageException("--rate must be in [10, 2000] Hz")
        val facesS = 6 * (1.5 + 4.0)
        if (calibrationMotion && duration <= facesS + 10.0) throw UsageException("--duration must be over ${fmt(facesS + 10.0)} s with --motion calibration")
        val settings = try {
            withErrors(settings(seed, rate, duration), o)
        } catch (e: IllegalArgumentException) {
            // The core's message names the setting; say it with the option's name.
            val m = e.message ?: "invalid simulation"
            val option = OPTION_OF_SETTING.entries.firstOrNull { m.startsWith(it.key + " ") }
            throw UsageException(if (option == null) m else option.value + m.removePrefix(option.key))
        }
        val samples: ((SimulatedSample) -> Unit) -> Unit =
            if (calibrationMotion) CalibrationMotion(settings, turnS = duration - facesS)::forEach else MotionSimulator(settings)::forEach
        val path = Paths.get(output)
        val lower = output.lowercase()
        val command = (listOf("fusion simulate --duration ${fmt(duration)} --rate ${fmt(rate)} --seed $seed") +
            listOfNotNull(if (calibrationMotion) "--motion calibration" else null) +
            ERROR_OPTIONS.mapNotNull { name -> o.value(name)?.let { "$name $it" } }).joinToString(" ")
        when {
            lower.endsWith(".csv") || lower.endsWith(".csv.gz") -> writeTable(outputs.file(output, emptyList()), samples, lower.endsWith(".gz"))
            lower.endsWith(".zip") -> {
                val zip = outputs.file(output, emptyList())
                val tmp = Files.createTempDirectory("fusion-simulate")
                val dir = tmp.resolve(path.fileName.toString().removeSuffix(".zip").removeSuffix(".ZIP"))
                try {
                    writeSession(dir, samples, rate, seed, command)
                    zip.use { SessionArchive.zip(dir, it, entryTimeMs = START_WALL_CLOCK_MS) }
                } finally {
                    tmp.toFile().deleteRecursively()
                }
            }
            else -> {
                val dir = outputs.folder(output, emptyList())
                // Name the session the user asked for, not the folder it is written in aside.
                try {
                    writeSession(dir, samples, rate, seed, command)
                } catch (e: java.io.IOException) {
                    throw java.nio.file.FileSystemException(output, null, dev.motionfusion.core.io.AtomicFiles.reason(e))
                }
            }
        }
        out.println("$output: $written samples, ${fmt(duration)} s at ${fmt(rate)} Hz ($command)")
        return ExitCode.OK
    }

    private companion object {
        /** The option of each simulation setting the core's messages name. */
        val OPTION_OF_SETTING = mapOf(
            "magSoftIron" to "--soft-iron", "accMisalignment" to "--acc-scale", "gyroScaleError" to "--gyro-scale-error",
            "accRange" to "--acc-range", "gyroRange" to "--gyro-range", "gyroNoiseDensity" to "--gyro-noise-density",
            "accNoiseDensity" to "--acc-noise-density", "magNoise" to "--mag-noise", "fieldStrength" to "--field", "dip" to "--field",
            "rateHz" to "--rate", "durationS" to "--duration",
        )

        val ERROR_OPTIONS = listOf(
            "--hard-iron", "--soft-iron", "--gyro-bias", "--acc-offset", "--acc-scale", "--gyro-noise-density", "--acc-noise-density", "--mag-noise",
            "--violent", "--acc-range", "--gyro-range", "--gyro-scale-error", "--field", "--hard-iron-window",
            "--mag-disturbance",
        )

        /** The simulated recording's fixed wall-clock start (2025-11-26 12:00 UTC): reproducible output. */
        const val START_WALL_CLOCK_MS = 1_764_158_400_000L
    }

    /** [base] with the sensor errors given on the command line. */
    private fun withErrors(base: SimulationSettings, o: Options): SimulationSettings {
        fun numbers(name: String, counts: Set<Int>): DoubleArray? = o.value(name)?.let { text ->
            val parts = text.split(',')
            val v = parts.map { p -> p.trim().toDoubleOrNull()?.takeIf { it.isFinite() } ?: throw UsageException("$name expects numbers separated by commas, got '$text'") }
            if (v.size !in counts) throw UsageException("$name expects ${counts.joinToString(" or ")} numbers, got ${v.size}")
            v.toDoubleArray()
        }
        fun vector(name: String) = numbers(name, setOf(3))?.let { Vector3(it[0], it[1], it[2]) }
        fun matrix(name: String) = numbers(name, setOf(3, 6))?.let {
            if (it.size == 3) Matrix3.diagonal(it[0], it[1], it[2]) else Matrix3.symmetric(it[0], it[1], it[2], it[3], it[4], it[5])
        }
        fun density(name: String) = o.double(name)?.also { if (it < 0.0) throw UsageException("$name must be ≥ 0") }
        val hardIron = vector("--hard-iron")
        val ironWindow = numbers("--hard-iron-window", setOf(2))?.let {
            if (hardIron == null) throw UsageException("--hard-iron-window needs --hard-iron")
            if (it[0] < 0.0 || it[1] <= it[0]) throw UsageException("--hard-iron-window expects S,E with 0 ≤ S < E")
            TimeWindow(it[0], it[1])
        }
        val field = numbers("--field", setOf(2))?.also {
            if (it[0] <= 0.0 || it[0] > 1000.0) throw UsageException("--field strength must be in (0, 1000] µT")
            if (kotlin.math.abs(it[1]) > 90.0) throw UsageException("--field dip must be in [−90, 90]°")
        }
        val violent = o.value("--violent")?.let { text ->
            text.split(',').map { item ->
                val at = item.indexOf('@')
                val kind = if (at > 0) ViolentMotionKind.entries.firstOrNull { it.name.equals(item.substring(0, at).trim(), ignoreCase = true) } else null
                val start = if (at > 0) item.substring(at + 1).trim().toDoubleOrNull() else null
                if (kind == null || start == null || !start.isFinite() || start < 0.0 || start + kind.durationS > base.durationS) {
                    throw UsageException("--violent expects KIND@S with KIND one of drop, fall, shake, throw and the motion inside --duration, got '$item'")
                }
                ViolentMotion(kind, start)
            }
        }
        val magDisturbances = o.value("--mag-disturbance")?.let { text ->
            text.split(',').map { item ->
                val at = item.indexOf('@')
                val colon = item.indexOf(':', at + 1)
                val name = if (at > 0) item.substring(0, at).trim().lowercase() else ""
                val kind = when (name) {
                    "ferrous" -> MagneticDisturbanceKind.FERROUS_PASS
                    "hall" -> MagneticDisturbanceKind.WEAK_TILTED_HALL
                    else -> null
                }
                val start = if (at > 0 && colon > at) item.substring(at + 1, colon).trim().toDoubleOrNull() else null
                val length = if (colon > at) item.substring(colon + 1).trim().toDoubleOrNull() else null
                if (kind == null || start == null || length == null || !start.isFinite() || !length.isFinite() || start < 0.0 || length < 2.0 || start + length > base.durationS) {
                    throw UsageException("--mag-disturbance expects KIND@S:D with KIND ferrous or hall, D ≥ 2 s and the disturbance inside --duration, got '$item'")
                }
                MagneticDisturbance(kind, start, length)
            }
        }
        // A range of 0 would clip every reading to 0; without the option nothing is clipped.
        fun range(name: String, max: Double) = o.double(name)?.also {
            if (!(it > 0.0) || it > max) throw UsageException("$name must be in (0, ${fmt(max)}] (leave it out for no clipping), got ${fmt(it)}")
        }
        val scale = o.double("--gyro-scale-error")?.also { if (kotlin.math.abs(it) >= 0.5) throw UsageException("--gyro-scale-error must be in (−0.5, 0.5)") }
        return base.copy(
            violentMotions = violent ?: base.violentMotions,
            magDisturbances = magDisturbances ?: base.magDisturbances,
            // Still outside the violent motions, which replace the rest where they fall.
            restWindows = if (violent != null) listOf(TimeWindow(0.0, base.durationS + 1.0)) else base.restWindows,
            accRange = range("--acc-range", 2000.0) ?: base.accRange,
            gyroRange = range("--gyro-range", 200.0) ?: base.gyroRange,
            gyroScaleError = scale ?: base.gyroScaleError,
            fieldStrength = field?.get(0) ?: base.fieldStrength,
            dip = field?.let { Math.toRadians(it[1]) } ?: base.dip,
            hardIron = hardIron ?: base.hardIron,
            hardIronWindow = ironWindow ?: if (hardIron != null) TimeWindow(0.0, base.durationS + 1.0) else base.hardIronWindow,
            magSoftIron = matrix("--soft-iron") ?: base.magSoftIron,
            gyroBias = vector("--gyro-bias") ?: base.gyroBias,
            accOffset = vector("--acc-offset") ?: base.accOffset,
            accMisalignment = matrix("--acc-scale") ?: base.accMisalignment,
            gyroNoiseDensity = density("--gyro-noise-density") ?: base.gyroNoiseDensity,
            accNoiseDensity = density("--acc-noise-density") ?: base.accNoiseDensity,
            magNoise = density("--mag-noise") ?: base.magNoise,
        )
    }

    private fun fmt(v: Double) = if (v == Math.rint(v)) v.toLong().toString() else v.toString()

    private fun settings(seed: Long, rate: Double, duration: Double) = SimulationSettings(
        seed = seed,
        rateHz = rate,
        durationS = duration,
        restWindows = listOf(TimeWindow(0.0, 2.0), TimeWindow(duration - 2.0, duration + 1.0)),
        gyroBias = Vector3(0.01, -0.02, 0.015),
        timestampJitter = minOf(0.0002, 0.2 / rate),
    )

    /** Samples written by the last run (the simulation streams to the output, never held in memory). */
    private var written = 0L

    private fun writeTable(file: java.io.OutputStream, samples: ((SimulatedSample) -> Unit) -> Unit, gzip: Boolean) {
        ImuTableWriter(file, gzip, magnetometer = true).use { w ->
            samples { x ->
                written++
                w.row(x.timestampNs * 1e-9, x.gyro, x.acc, x.mag)
            }
        }
    }

    private fun writeSession(dir: Path, samples: ((SimulatedSample) -> Unit) -> Unit, rate: Double, seed: Long, command: String) {
        val base = 1_000_000_000_000L // an elapsedRealtimeNanos-like origin (about 17 minutes after boot)
        val period = (1e6 / rate).toInt()
        val meta = SessionMetadata(
            appVersion = Cli.VERSION,
            source = command,
            device = DeviceInfo("Motion Fusion", "MotionSimulator", "", 0),
            startAnchor = ClockAnchor(START_WALL_CLOCK_MS, base),
            sensors = listOf(
                SensorInfo(SessionStream.ACCELEROMETER, "simulated accelerometer", "dev.motionfusion", 1, requestedPeriodUs = period),
                SensorInfo(SessionStream.GYROSCOPE, "simulated gyroscope", "dev.motionfusion", 1, requestedPeriodUs = period),
                SensorInfo(SessionStream.MAGNETOMETER, "simulated magnetometer", "dev.motionfusion", 1, requestedPeriodUs = period),
                SensorInfo(SessionStream.ROTATION_VECTOR, "simulated rotation vector (truth + 2° heading offset + 0.3° noise)", "dev.motionfusion", 1, requestedPeriodUs = 4 * period),
            ),
            filterSettings = null,
        )
        val random = Random(seed xor 0x5EED)
        val offset = Quaternion.fromAxisAngle(Vector3.UNIT_Z, Math.toRadians(2.0))
        SessionWriter.create(dir, meta).use { w ->
            var i = 0L
            samples { s ->
                written++
                val t = base + s.timestampNs
                w.accelerometer(t, s.acc.x.toFloat(), s.acc.y.toFloat(), s.acc.z.toFloat(), 3)
                w.magnetometer(t, s.mag.x.toFloat(), s.mag.y.toFloat(), s.mag.z.toFloat(), 3)
                w.gyroscope(t, s.gyro.x.toFloat(), s.gyro.y.toFloat(), s.gyro.z.toFloat(), 3)
                w.truth(t, s.truth.w, s.truth.x, s.truth.y, s.truth.z)
                if (i++ % 4 == 0L) {
                    val noise = Vector3(random.nextGaussian(), random.nextGaussian(), random.nextGaussian()) * Math.toRadians(0.3)
                    val rv = (offset * s.truth * Quaternion.fromRotationVector(noise)).normalized().canonical()
                    w.rotationVector(t, rv.x.toFloat(), rv.y.toFloat(), rv.z.toFloat(), rv.w.toFloat(), Math.toRadians(5.0).toFloat(), 3)
                }
            }
        }
    }
}
