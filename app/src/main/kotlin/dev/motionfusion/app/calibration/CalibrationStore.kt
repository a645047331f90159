package dev.motionfusion.app.calibration

import android.content.SharedPreferences
import android.os.Build
import dev.motionfusion.app.platform.MainThreadPolicy
import dev.motionfusion.core.calib.Calibration
import dev.motionfusion.core.calib.CalibrationJson
import dev.motionfusion.core.io.AtomicFiles
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.session.SessionCalibration
import kotlinx.coroutines.CoroutineDispatcher
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.Job
import kotlinx.coroutines.flow.MutableStateFlow
import kotlinx.coroutines.flow.StateFlow
import kotlinx.coroutines.flow.asStateFlow
import kotlinx.coroutines.launch
import kotlinx.coroutines.withContext
import java.io.File
import java.io.IOException
import java.security.MessageDigest

/**
 * Which device a calibration belongs to: maker, model and the sensors it was fitted with (name
 * and vendor). A backup restored onto another phone, or a phone whose sensors changed, does not
 * find the other one's calibration.
 */
data class DeviceKey(val manufacturer: String, val model: String, val sensors: List<String>) {
    /** In words, as stored in the file's `device` member. */
    val description: String get() = (listOf("$manufacturer $model".trim()) + sensors).joinToString("; ")

    /** The file of this device: maker and model readable, then a hash of the whole key. */
    val fileName: String get() {
        val slug = "$manufacturer-$model".lowercase().replace(Regex("[^a-z0-9]+"), "-").trim('-').take(40).ifEmpty { "device" }
        val hash = MessageDigest.getInstance("SHA-256").digest(description.toByteArray(Charsets.UTF_8))
        return slug + "-" + hash.take(6).joinToString("") { "%02x".format(it) } + ".json"
    }

    companion object {
        /** This phone (android.os.Build) with [sensors]. */
        fun thisDevice(sensors: List<String>) = DeviceKey(Build.MANUFACTURER ?: "", Build.MODEL ?: "", sensors)
    }
}

/**
 * The latest accepted calibration of one device, in `DIR/<DeviceKey.fileName>` as the
 * calibration file of docs/CALIBRATION.md (core's CalibrationJson), replaced atomically (core's
 * AtomicFiles), read and written on [io] only. Each sensor keeps its latest accepted fit: a new
 * magnetometer fit replaces the stored magnetometer and leaves the stored accelerometer.
 *
 * The file and the setting are read once, on [io], when the store is made; [dir] and [prefs]
 * are resolved there on first use (the store itself is made on the main thread, which must not
 * touch the disk). Until then [calibration] is null. A damaged file is moved aside to `<name>.damaged` (nothing lost)
 * and [problem] says why.
 *
 * For the recorder and the live filter (they only read memory: safe on any thread):
 * [active] and [sessionCalibration], once [awaitLoaded] has returned.
 */
class CalibrationStore(
    dir: () -> File,
    val device: DeviceKey,
    prefs: () -> SharedPreferences,
    private val io: CoroutineDispatcher,
    private val scope: CoroutineScope,
    private val files: AtomicFiles = AtomicFiles(),
) {
    private val dir by lazy(dir)
    private val prefs by lazy(prefs)
    private val file by lazy { File(this.dir, device.fileName) }
    private val current = MutableStateFlow<Calibration?>(null)
    private val use = MutableStateFlow(false)
    private val activeFlow = MutableStateFlow<Calibration?>(null)

    /** The stored calibration of this device (null: none, or not read yet). */
    val calibration: StateFlow<Calibration?> = current

    /** Setting "use the calibration in the live filter" (off by default; read with the file, on [io]). */
    val useInLiveFilter: StateFlow<Boolean> = use.asStateFlow()

    /**
     * The calibration the live filter applies: the stored one while [useInLiveFilter] is on,
     * else null. The capture applies it as core's `CalibrationRoute` says (an uncalibrated
     * stream corrected replaces the calibrated one).
     */
    val active: StateFlow<Calibration?> = activeFlow.asStateFlow()

    /** Why the stored file could not be read or written, or null. */
    @Volatile var problem: String? = null
        private set

    /** The setting was chosen before the stored one was read: the choice wins. */
    private var useChosen = false

    private val loaded: Job = scope.launch(io) {
        val stored = prefs().getBoolean(USE_IN_LIVE_FILTER, false)
        val read = read()
        synchronized(this@CalibrationStore) {
            if (!useChosen) use.value = stored
            current.value = read
            update()
        }
    }

    private fun prefs(): SharedPreferences {
        MainThreadPolicy.checkNotMainThread()
        return prefs
    }

    /** Turns the setting on or off (stored in the background). */
    fun setUseInLiveFilter(on: Boolean) {
        synchronized(this) {
            useChosen = true
            use.value = on
            update()
        }
        scope.launch(io) {
            val p = prefs()
            // Stores the latest choice, whatever order the writes run in ([io] need not be serial).
            synchronized(writing) { p.edit().putBoolean(USE_IN_LIVE_FILTER, use.value).apply() }
        }
    }

    private val writing = Any()

    private fun update() {
        activeFlow.value = if (use.value) current.value else null
    }

    /**
     * For a session's meta.json (member `calibration`, docs/CALIBRATION.md): the stored
     * calibration and whether the setting asks the live filter to use it; null when nothing is
     * stored. The recording stays raw: replay can apply it or not.
     */
    fun sessionCalibration(): SessionCalibration? = current.value?.let { SessionCalibration(it, use.value) }

    /** Waits until the file has been read. */
    suspend fun awaitLoaded(): Unit = loaded.join()

    /**
     * Stores the accepted sensors of [fitted] over the stored ones and returns what is now
     * stored. Throws an IOException (a FileSystemException naming the file) when it cannot be written.
     */
    suspend fun accept(fitted: Calibration): Calibration = withContext(io) {
        loaded.join()
        val old = current.value
        val merged = Calibration(
            magnetometer = fitted.magnetometer ?: old?.magnetometer,
            gyroscope = fitted.gyroscope ?: old?.gyroscope,
            accelerometer = fitted.accelerometer ?: old?.accelerometer,
            source = fitted.source,
            device = device.description,
        )
        try {
            dir.mkdirs()
            files.write(file.toPath(), CalibrationJson.write(merged).toByteArray(Charsets.UTF_8))
        } catch (e: IOException) {
            problem = "${file.name}: ${AtomicFiles.reason(e)}"
            throw e
        }
        problem = null
        synchronized(this@CalibrationStore) {
            current.value = merged
            update()
        }
        merged
    }

    private fun read(): Calibration? {
        MainThreadPolicy.checkNotMainThread()
        if (!file.isFile) return null
        return try {
            CalibrationJson.parse(file.readText(Charsets.UTF_8), file.name)
        } catch (e: DataFormatException) {
            setAside("${e.message}")
        } catch (e: IOException) {
            problem = "${file.name}: ${AtomicFiles.reason(e)}"
            null
        }
    }

    private fun setAside(reason: String): Calibration? {
        val aside = File(dir, file.name + ".damaged")
        val moved = file.renameTo(aside)
        problem = if (moved) "$reason (kept as ${aside.name})" else reason
        return null
    }

    companion object {
        const val PREFS = "calibration"
        internal const val USE_IN_LIVE_FILTER = "use_in_live_filter"
    }
}
