package dev.motionfusion.app.sensor

import dev.motionfusion.core.event.SessionStream

/**
 * The session streams that come from an Android sensor (accelerometer, gyroscope,
 * magnetometer, their uncalibrated forms, rotation vector, game rotation vector): what the
 * capture registers and the recorder writes, in [SessionStream]'s units and value order.
 */
internal object SensorStreams {
    val all: List<SessionStream> = SessionStream.entries.filter { it.androidType != 0 }

    private val byOrdinal = SessionStream.entries.toTypedArray()
    private val byType = arrayOfNulls<SessionStream>(64).also { t -> all.forEach { t[it.androidType] = it } }
    private val kinds = arrayOfNulls<SensorKind>(SessionStream.entries.size).also { k ->
        for (kind in SensorKind.entries) all.firstOrNull { it.androidType == kind.androidType }?.let { k[it.ordinal] = kind }
    }

    /** The most values a sensor stream has (uncalibrated: 3 + 3 bias). */
    val maxValues: Int = all.maxOf { it.valueCount }

    fun ofOrdinal(ordinal: Int): SessionStream = byOrdinal[ordinal]

    /** The stream of an Android sensor type, or null for a type that is not recorded. Allocation-free. */
    fun ofAndroidType(type: Int): SessionStream? = if (type in byType.indices) byType[type] else null

    /** The live screen's [SensorKind] of [stream], or null for the streams it does not show (uncalibrated). */
    fun kindOf(stream: SessionStream): SensorKind? = kinds[stream.ordinal]

}
