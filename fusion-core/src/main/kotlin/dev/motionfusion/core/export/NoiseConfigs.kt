package dev.motionfusion.core.export

import dev.motionfusion.core.calib.AllanResult
import dev.motionfusion.core.calib.DiscreteNoise
import dev.motionfusion.core.calib.yamlNumber
import dev.motionfusion.core.input.Recording
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.io.ZipFolder
import java.io.OutputStream
import java.nio.charset.StandardCharsets
import java.nio.file.Files
import java.nio.file.Path
import java.util.Locale

/**
 * The four continuous-time noise figures of kalibr's imu.yaml (as `fusion allan` writes it), the
 * rate it names (update_rate, Hz; null when it names none), and the file itself.
 */
public class NoiseModel private constructor(
    /** The imu.yaml it was read from, as written. */
    public val text: String,
    internal val figures: Map<String, Double>,
    /** The rate the file names (update_rate, Hz); null when it names none. */
    public val rateHz: Double?,
) {
    /** rad/s/√Hz, continuous time. */
    public val gyroscopeNoiseDensity: Double get() = figures.getValue("gyroscope_noise_density")
    /** rad/s²/√Hz, continuous time. */
    public val gyroscopeRandomWalk: Double get() = figures.getValue("gyroscope_random_walk")
    /** m/s²/√Hz, continuous time. */
    public val accelerometerNoiseDensity: Double get() = figures.getValue("accelerometer_noise_density")
    /** m/s³/√Hz, continuous time. */
    public val accelerometerRandomWalk: Double get() = figures.getValue("accelerometer_random_walk")

    public companion object {
        /** The four keys of kalibr's imu.yaml. */
        @JvmField
        public val KEYS: List<String> = listOf("gyroscope_noise_density", "gyroscope_random_walk", "accelerometer_noise_density", "accelerometer_random_walk")

        /** Shortest still recording, s, whose Allan deviation gives a noise density (clusters of 1 s, enough of them). */
        public const val MIN_ALLAN_S: Double = 60.0

        /** The noise model in the file [path] (kalibr's imu.yaml, as `fusion allan` writes it). */
        @JvmStatic
        public fun read(path: Path): NoiseModel = parse(String(Files.readAllBytes(path), StandardCharsets.UTF_8), path.toString())

        /**
         * The noise model of an Allan analysis of the still recording [input] (its kalibr imu.yaml, made by
         * [source]). @throws DataFormatException when the recording is too short for noise figures or was not
         * still ([checkUsable]), or a figure could not be read off (a stream missing).
         */
        internal fun of(result: AllanResult, source: String, input: String): NoiseModel {
            checkUsable(result, input)
            return parse(result.kalibrYaml(source), "the noise model of $input")
        }

        /** @throws DataFormatException when [result] is too short for noise figures (under [MIN_ALLAN_S] s). */
        @JvmStatic
        public fun checkLongEnough(result: AllanResult, input: String) {
            if ((result.gyroscope?.tau?.size ?: 0) < 3 && (result.accelerometer?.tau?.size ?: 0) < 3) {
                throw DataFormatException(input, 0, 0, "too short for an Allan deviation: needs a gyroscope or accelerometer stream of at least a few hundred samples")
            }
            val seconds = listOfNotNull(result.gyroscope, result.accelerometer).maxOfOrNull { it.samples / it.rateHz } ?: 0.0
            if (!(seconds >= MIN_ALLAN_S)) {
                throw DataFormatException(input, 0, 0, "${String.format(Locale.ROOT, "%.1f", seconds)} s of samples is too short for noise figures: " +
                    "the noise density needs at least ${MIN_ALLAN_S.toInt()} s of still recording (the random walk and bias instability hours)")
            }
        }

        /**
         * [checkLongEnough], and every axis has the white-noise line a still sensor's Allan deviation has
         * (slope −½ about τ = 1 s): a phone that moved has none, and its figures would be NaN or meaningless.
         * @throws DataFormatException naming the axes without one.
         */
        @JvmStatic
        public fun checkUsable(result: AllanResult, input: String) {
            checkLongEnough(result, input)
            val missing = ArrayList<String>()
            for ((name, terms) in listOf("gyroscope" to result.gyroscopeTerms, "accelerometer" to result.accelerometerTerms)) {
                terms?.forEachIndexed { axis, t -> if (!t.whiteNoise.isFinite()) missing += "$name ${"xyz"[axis]}" }
            }
            if (missing.isNotEmpty()) {
                throw DataFormatException(input, 0, 0, "no white-noise line (slope -1/2 near 1 s) on the ${missing.joinToString(", ")}: " +
                    "the phone moved or was handled; noise figures need it lying untouched throughout")
            }
        }

        /** The figures of [text] (kalibr's imu.yaml); [source] names it in errors. */
        @JvmStatic
        public fun parse(text: String, source: String): NoiseModel {
            val figures = LinkedHashMap<String, Double>()
            var rate: Double? = null
            text.lines().forEachIndexed { i, raw ->
                val line = raw.substringBefore('#').trim()
                val key = line.substringBefore(':').trim()
                val v = line.substringAfter(':').trim()
                if (key in KEYS) {
                    val d = v.toDoubleOrNull()
                    if (d == null || !d.isFinite() || d < 0) {
                        throw DataFormatException(source, (i + 1).toLong(), raw.indexOf(v).coerceAtLeast(0) + 1, "$key: '$v' is not a noise figure (a finite number ≥ 0)")
                    }
                    figures[key] = d
                } else if (key == "update_rate") {
                    rate = v.toDoubleOrNull()?.takeIf { it.isFinite() && it > 0 }
                }
            }
            val missing = KEYS.filter { it !in figures }
            if (missing.isNotEmpty()) throw DataFormatException(source, 0, 0, "not a noise model: ${missing.joinToString(", ")} missing (kalibr's imu.yaml, as fusion allan writes it)")
            return NoiseModel(text, figures, rate)
        }
    }
}

/**
 * The noise model in the configuration files of the VIO/SLAM stacks, each with the conversion it
 * needs (docs/EXPORT.md, "Noise models"): kalibr and OpenVINS take the continuous-time figures
 * and discretise them themselves, as does ORB-SLAM3 (with IMU.Frequency); VINS-Mono/Fusion take
 * per-sample figures at the IMU rate.
 */
public object NoiseConfigs {
    /**
     * File name → content of every configuration, from [m] at [rateHz]; [source] says where it came from:
     * imu.yaml (kalibr), kalibr_imu_chain.yaml (OpenVINS), vins_imu.yaml (VINS-Mono/Fusion), orbslam3_imu.yaml.
     */
    @JvmStatic
    public fun all(m: NoiseModel, rateHz: Double, source: String): Map<String, String> = linkedMapOf(
        "imu.yaml" to m.text,
        "kalibr_imu_chain.yaml" to openVins(m, rateHz, source),
        "vins_imu.yaml" to vins(m, rateHz, source),
        "orbslam3_imu.yaml" to orbSlam3(m, rateHz, source),
    )

    /**
     * Every configuration of [all] from the still recording [rec]: its Allan deviation, the noise model
     * read off it and the configurations at the recording's rate; [generator] names what made them
     * (e.g. "fusion allan 1.0"). @throws DataFormatException when [rec] is too short for noise figures.
     */
    @JvmStatic
    @JvmOverloads
    public fun fromStillRecording(rec: Recording, generator: String, progress: ((Long) -> Unit)? = null): Map<String, String> {
        val result = rec.events().use { AllanResult.run(it, rec.streams, progress) }
        val source = "$generator from ${rec.name}"
        val model = NoiseModel.of(result, source, rec.name)
        val rate = model.rateHz ?: throw DataFormatException(rec.name, 0, 0, "no sample rate for the noise configurations")
        return all(model, rate, source)
    }

    /**
     * [fromStillRecording] written to [out] as a zip, the files inside the folder [name] (made first under
     * [scratch] and removed again). Does not close [out].
     */
    @JvmStatic
    @JvmOverloads
    public fun writeZip(rec: Recording, generator: String, out: OutputStream, name: String, scratch: Path, progress: ((Long) -> Unit)? = null) {
        val configs = fromStillRecording(rec, generator, progress)
        val folder = Files.createTempDirectory(scratch, ".noise-")
        try {
            for ((file, text) in configs) Files.write(folder.resolve(file), text.toByteArray(StandardCharsets.UTF_8))
            ZipFolder.write(folder, name, out)
        } finally {
            ZipFolder.removeTree(folder)
        }
    }

    private fun num(v: Double) = yamlNumber(v)

    private fun StringBuilder.continuous(m: NoiseModel, indent: String = "") {
        appendLine("${indent}accelerometer_noise_density: ${num(m.accelerometerNoiseDensity)}  # m/s^2/sqrt(Hz), continuous time")
        appendLine("${indent}accelerometer_random_walk: ${num(m.accelerometerRandomWalk)}  # m/s^3/sqrt(Hz), continuous time")
        appendLine("${indent}gyroscope_noise_density: ${num(m.gyroscopeNoiseDensity)}  # rad/s/sqrt(Hz), continuous time")
        appendLine("${indent}gyroscope_random_walk: ${num(m.gyroscopeRandomWalk)}  # rad/s^2/sqrt(Hz), continuous time")
    }

    /** The discrete figures of kalibr's model at [rateHz], as comment lines. */
    internal fun discreteComment(m: NoiseModel, rateHz: Double): String = buildString {
        appendLine("# Discrete time, per sample at f = ${num(rateHz)} Hz (dt = ${num(1.0 / rateHz)} s): white noise sigma_d = density * sqrt(f),")
        appendLine("# bias random walk sigma_bd = random_walk / sqrt(f) (kalibr's IMU noise model):")
        appendLine("#   accelerometer sigma_d ${num(DiscreteNoise.white(m.accelerometerNoiseDensity, rateHz))} m/s^2, sigma_bd ${num(DiscreteNoise.randomWalk(m.accelerometerRandomWalk, rateHz))} m/s^2")
        appendLine("#   gyroscope sigma_d ${num(DiscreteNoise.white(m.gyroscopeNoiseDensity, rateHz))} rad/s, sigma_bd ${num(DiscreteNoise.randomWalk(m.gyroscopeRandomWalk, rateHz))} rad/s")
    }

    /** OpenVINS's kalibr_imu_chain.yaml (its EuRoC example's keys). */
    internal fun openVins(m: NoiseModel, rateHz: Double, source: String): String = buildString {
        appendLine("%YAML:1.0")
        appendLine("# $source")
        appendLine("# OpenVINS IMU configuration (kalibr_imu_chain.yaml). OpenVINS reads kalibr's CONTINUOUS-TIME figures")
        appendLine("# and discretises them at each step itself (white noise sigma^2 / dt, bias random walk sigma^2 * dt).")
        appendLine("# T_i_b identity: the IMU is the body (the phone's device axes: ${About.AXES}).")
        appendLine("# No intrinsic calibration: Tw, Ta, R_IMUtoGYRO, R_IMUtoACC identity, Tg zero.")
        append(discreteComment(m, rateHz))
        appendLine("imu0:")
        appendLine("  T_i_b:")
        for (r in 0 until 4) appendLine("    - [${(0 until 4).joinToString(", ") { if (it == r) "1.0" else "0.0" }}]")
        continuous(m, "  ")
        appendLine("  rostopic: /imu0")
        appendLine("  time_offset: 0.0")
        appendLine("  update_rate: ${num(rateHz)}  # Hz")
        appendLine("  model: \"kalibr\"")
        for (name in listOf("Tw", "R_IMUtoGYRO", "Ta", "R_IMUtoACC", "Tg")) {
            appendLine("  $name:")
            for (r in 0 until 3) appendLine("    - [ ${(0 until 3).joinToString(", ") { if (it == r && name != "Tg") "1.0" else "0.0" }} ]")
        }
    }

    /** The imu parameters of a VINS-Mono / VINS-Fusion configuration. */
    internal fun vins(m: NoiseModel, rateHz: Double, source: String): String = buildString {
        val sf = kotlin.math.sqrt(rateHz)
        appendLine("%YAML:1.0")
        appendLine("# $source")
        appendLine("# IMU noise for VINS-Mono / VINS-Fusion: the imu parameters of the estimator's configuration")
        appendLine("# (keep its g_norm). VINS takes DISCRETE figures at the IMU rate f = ${num(rateHz)} Hz (its")
        appendLine("# integration_base.h: acc_n^2 is the variance of one sample's white noise, and the bias changes by")
        appendLine("# acc_w * dt per sample), so from kalibr's continuous figures:")
        appendLine("#   acc_n = accelerometer_noise_density * sqrt(f)    gyr_n = gyroscope_noise_density * sqrt(f)")
        appendLine("#   acc_w = accelerometer_random_walk * sqrt(f)      gyr_w = gyroscope_random_walk * sqrt(f)")
        appendLine("# (acc_w * dt = random_walk * sqrt(dt): kalibr's per-sample bias random walk).")
        appendLine("# Continuous figures: accelerometer ${num(m.accelerometerNoiseDensity)} m/s^2/sqrt(Hz), ${num(m.accelerometerRandomWalk)} m/s^3/sqrt(Hz);")
        appendLine("# gyroscope ${num(m.gyroscopeNoiseDensity)} rad/s/sqrt(Hz), ${num(m.gyroscopeRandomWalk)} rad/s^2/sqrt(Hz).")
        appendLine("# VINS's own example configurations use values one to two orders above a sensor's Allan figures")
        appendLine("# (unmodelled motion and temperature effects): raise these if the estimate diverges.")
        appendLine("acc_n: ${num(m.accelerometerNoiseDensity * sf)}  # m/s^2")
        appendLine("gyr_n: ${num(m.gyroscopeNoiseDensity * sf)}  # rad/s")
        appendLine("acc_w: ${num(m.accelerometerRandomWalk * sf)}  # m/s^3")
        appendLine("gyr_w: ${num(m.gyroscopeRandomWalk * sf)}  # rad/s^2")
    }

    /** The IMU entries of an ORB-SLAM3 settings file. */
    internal fun orbSlam3(m: NoiseModel, rateHz: Double, source: String): String = buildString {
        appendLine("%YAML:1.0")
        appendLine("# $source")
        appendLine("# IMU noise for ORB-SLAM3: the IMU entries of its settings file (add IMU.T_b_c1, the camera-to-IMU")
        appendLine("# transform of a camera-IMU calibration). ORB-SLAM3 reads CONTINUOUS-TIME figures and IMU.Frequency")
        appendLine("# and discretises them itself (noise * sqrt(IMU.Frequency), walk / sqrt(IMU.Frequency)).")
        append(discreteComment(m, rateHz))
        appendLine("IMU.NoiseGyro: ${num(m.gyroscopeNoiseDensity)}  # rad/s/sqrt(Hz)")
        appendLine("IMU.NoiseAcc: ${num(m.accelerometerNoiseDensity)}  # m/s^2/sqrt(Hz)")
        appendLine("IMU.GyroWalk: ${num(m.gyroscopeRandomWalk)}  # rad/s^2/sqrt(Hz)")
        appendLine("IMU.AccWalk: ${num(m.accelerometerRandomWalk)}  # m/s^3/sqrt(Hz)")
        appendLine("IMU.Frequency: ${num(rateHz)}  # Hz")
    }
}
