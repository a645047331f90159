package dev.motionfusion.app.build

import android.content.pm.ServiceInfo
import dev.motionfusion.app.build.BuildFiles.androidName
import dev.motionfusion.app.build.BuildFiles.child
import dev.motionfusion.app.build.BuildFiles.children
import dev.motionfusion.app.record.RecordingService
import dev.motionfusion.app.stream.StreamService
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

/**
 * Each foreground service's type (the recording's and the live stream's), the permission Android 14+
 * requires for that type, and the type the service passes to startForeground belong together: this
 * test fails when one of them changes without the others.
 */
class ForegroundServiceTest {
    private val manifest = BuildFiles.parse(BuildFiles.manifest)
    private val permissions = manifest.children("uses-permission").map { it.androidName() }.toSet()

    /** Manifest type name → the ServiceInfo constant and the permission it needs (Android 14 ServiceInfo docs). */
    private val types = mapOf(
        "health" to (ServiceInfo.FOREGROUND_SERVICE_TYPE_HEALTH to "android.permission.FOREGROUND_SERVICE_HEALTH"),
        "dataSync" to (ServiceInfo.FOREGROUND_SERVICE_TYPE_DATA_SYNC to "android.permission.FOREGROUND_SERVICE_DATA_SYNC"),
        "specialUse" to (ServiceInfo.FOREGROUND_SERVICE_TYPE_SPECIAL_USE to "android.permission.FOREGROUND_SERVICE_SPECIAL_USE"),
        "location" to (ServiceInfo.FOREGROUND_SERVICE_TYPE_LOCATION to "android.permission.FOREGROUND_SERVICE_LOCATION"),
        "connectedDevice" to (ServiceInfo.FOREGROUND_SERVICE_TYPE_CONNECTED_DEVICE to "android.permission.FOREGROUND_SERVICE_CONNECTED_DEVICE"),
    )

    /** Each foreground service of the app (its class name's end) and the type it passes to startForeground. */
    private val services = mapOf(
        ".record.RecordingService" to RecordingService.FOREGROUND_SERVICE_TYPE,
        ".stream.StreamService" to StreamService.FOREGROUND_SERVICE_TYPE,
    )

    private fun service(name: String) = manifest.child("application")!!.children("service").single { it.androidName().endsWith(name) }

    @Test
    fun `the manifest's type, its permission and the type passed to startForeground agree`() {
        for ((name, passed) in services) {
            val declared = service(name).getAttributeNS(BuildFiles.ANDROID, "foregroundServiceType")
            val (constant, permission) = types[declared] ?: error("$name: foregroundServiceType '$declared' not known to this test")
            assertEquals(constant, passed, "$name: type passed to startForeground")
            assertTrue(permission in permissions, "$permission missing for type $declared")
        }
        assertTrue("android.permission.FOREGROUND_SERVICE" in permissions)
        // Every service of the app is one of these (a new one is checked too).
        val declaredServices = manifest.child("application")!!.children("service").map { it.androidName() }.filter { it.startsWith(".") }
        assertEquals(services.keys, declaredServices.toSet())
    }

    @Test
    fun `the type's own requirements are met`() {
        for (name in services.keys) requirementsMet(service(name))
    }

    private fun requirementsMet(service: org.w3c.dom.Element) {
        when (val declared = service.getAttributeNS(BuildFiles.ANDROID, "foregroundServiceType")) {
            // Play reviews a specialUse service by the subtype the manifest gives it.
            "specialUse" -> {
                val subtype = service.children("property").singleOrNull { it.androidName() == "android.app.PROPERTY_SPECIAL_USE_FGS_SUBTYPE" }
                assertTrue(subtype != null, "a specialUse service needs its PROPERTY_SPECIAL_USE_FGS_SUBTYPE property")
                assertTrue(subtype!!.getAttributeNS(BuildFiles.ANDROID, "value").length >= 40, "the subtype says what the service does")
            }
            // FOREGROUND_SERVICE_HEALTH also needs ACTIVITY_RECOGNITION, BODY_SENSORS or HIGH_SAMPLING_RATE_SENSORS.
            "health" -> {
                val anyOf = setOf("android.permission.ACTIVITY_RECOGNITION", "android.permission.BODY_SENSORS", "android.permission.HIGH_SAMPLING_RATE_SENSORS")
                assertTrue(permissions.any { it in anyOf }, "$permissions")
            }
            // Android 14+ starts a connectedDevice service only for an app that holds one of these (ServiceInfo docs).
            "connectedDevice" -> {
                val anyOf = setOf(
                    "android.permission.BLUETOOTH_ADVERTISE", "android.permission.BLUETOOTH_CONNECT", "android.permission.BLUETOOTH_SCAN",
                    "android.permission.CHANGE_NETWORK_STATE", "android.permission.CHANGE_WIFI_STATE", "android.permission.CHANGE_WIFI_MULTICAST_STATE",
                    "android.permission.NFC", "android.permission.TRANSMIT_IR", "android.permission.UWB_RANGING",
                )
                assertTrue(permissions.any { it in anyOf }, "$permissions")
            }
            else -> error("no requirements known for type $declared")
        }
    }
}
