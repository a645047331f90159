package dev.motionfusion.app.record

import android.hardware.Sensor
import android.os.Build
import android.os.SystemClock
import dev.motionfusion.core.filter.FilterSettings

/** One recorded sensor as Android describes it (units: range and resolution in the stream's SI unit, delays µs). */
internal data class RecordedSensor(
    val stream: RecordStream,
    val name: String,
    val vendor: String,
    val type: Int,
    val stringType: String,
    val version: Int,
    val maximumRange: Float,
    val resolution: Float,
    val powerMa: Float,
    val minDelayUs: Int,
    val maxDelayUs: Int,
    val fifoReservedEventCount: Int,
    val fifoMaxEventCount: Int,
    val requestedPeriodUs: Int,
) {
    companion object {
        fun of(stream: RecordStream, s: Sensor, requestedPeriodUs: Int) = RecordedSensor(
            stream, s.name ?: "", s.vendor ?: "", s.type, s.stringType ?: "", s.version,
            s.maximumRange, s.resolution, s.power, s.minDelay, s.maxDelay,
            s.fifoReservedEventCount, s.fifoMaxEventCount, requestedPeriodUs,
        )
    }
}

/** What a session's metadata says about the recording, taken when it starts. */
internal data class RecordingMetadata(
    val appVersion: String,
    val deviceManufacturer: String,
    val deviceModel: String,
    val androidRelease: String,
    val androidSdk: Int,
    val sensors: List<RecordedSensor>,
    /** Wall clock anchor: `System.currentTimeMillis()` … */
    val startWallClockMs: Long,
    /** … and `SystemClock.elapsedRealtimeNanos()` (the SensorEvent.timestamp base) taken together. */
    val startElapsedRealtimeNs: Long,
    val filterSettings: FilterSettings,
) {
    companion object {
        fun now(appVersion: String, sensors: List<RecordedSensor>, settings: FilterSettings): RecordingMetadata {
            // Bracket the wall clock read with two elapsed reads and keep their midpoint.
            val e0 = SystemClock.elapsedRealtimeNanos()
            val wall = System.currentTimeMillis()
            val e1 = SystemClock.elapsedRealtimeNanos()
            return RecordingMetadata(
                appVersion, Build.MANUFACTURER ?: "", Build.MODEL ?: "", Build.VERSION.RELEASE ?: "",
                Build.VERSION.SDK_INT, sensors, wall, e0 + (e1 - e0) / 2, settings,
            )
        }
    }
}
